#pragma once
// Minimal command-line parsing for the `hexcover` subcommands: positional arguments and
// `--name value` / `--flag` options. Usage errors throw UsageError (exit status 2).

#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace hexcover::cli {

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Arguments {
 public:
  /// Parses argv[first..argc). `valued` lists the options that take a value (e.g. "-o",
  /// "--edge-length"); `flags` those that do not. Anything else starting with '-' is a usage error.
  Arguments(int argc, char** argv, int first, const std::set<std::string>& valued,
            const std::set<std::string>& flags);

  const std::vector<std::string>& positional() const { return positional_; }
  /// The one positional argument at `index`, or a UsageError naming `what`.
  const std::string& positional(std::size_t index, const std::string& what) const;
  /// Fails with a UsageError when there are more than `count` positional arguments.
  void expectPositionalCount(std::size_t count) const;

  bool has(const std::string& name) const { return values_.count(name) > 0 || flags_.count(name) > 0; }
  std::optional<std::string> value(const std::string& name) const;
  std::optional<double> number(const std::string& name) const;
  std::optional<long long> integer(const std::string& name) const;

 private:
  std::vector<std::string> positional_;
  std::map<std::string, std::string> values_;
  std::set<std::string> flags_;
};

}  // namespace hexcover::cli
