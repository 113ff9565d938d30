#include "clients/cli/arguments.h"

#include <cmath>

namespace hexcover::cli {

Arguments::Arguments(int argc, char** argv, int first, const std::set<std::string>& valued,
                     const std::set<std::string>& flags) {
  for (int i = first; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.size() > 1 && arg[0] == '-' && !std::isdigit(static_cast<unsigned char>(arg[1]))) {
      if (valued.count(arg)) {
        if (i + 1 >= argc) throw UsageError("option " + arg + " needs a value");
        values_[arg] = argv[++i];
      } else if (flags.count(arg)) {
        flags_.insert(arg);
      } else {
        throw UsageError("unknown option " + arg);
      }
    } else {
      positional_.push_back(arg);
    }
  }
}

const std::string& Arguments::positional(std::size_t index, const std::string& what) const {
  if (index >= positional_.size()) throw UsageError("missing argument: " + what);
  return positional_[index];
}

void Arguments::expectPositionalCount(std::size_t count) const {
  if (positional_.size() > count)
    throw UsageError("unexpected argument: " + positional_[count]);
}

std::optional<std::string> Arguments::value(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second;
}

std::optional<double> Arguments::number(const std::string& name) const {
  const auto text = value(name);
  if (!text) return std::nullopt;
  std::size_t used = 0;
  double parsed = 0.0;
  try {
    parsed = std::stod(*text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text->size() || !std::isfinite(parsed))
    throw UsageError("option " + name + " expects a number, got '" + *text + "'");
  return parsed;
}

std::optional<long long> Arguments::integer(const std::string& name) const {
  const auto text = value(name);
  if (!text) return std::nullopt;
  std::size_t used = 0;
  long long parsed = 0;
  try {
    parsed = std::stoll(*text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text->size())
    throw UsageError("option " + name + " expects a whole number, got '" + *text + "'");
  return parsed;
}

}  // namespace hexcover::cli
