// hexcover: command-line front end of the remeshing library.

#include <cstring>
#include <iostream>
#include <string_view>

#include "clients/cli/arguments.h"
#include "clients/cli/commands.h"
#include "core/common/error.h"
#include "core/common/memory.h"

namespace hexcover::cli {
namespace {

struct Subcommand {
  std::string_view name;
  std::string_view synopsis;
  Command run;
};

int printVersion(int, char**) {
  std::cout << "hexcover 0.1.0\n";
  return 0;
}

// One row per subcommand; each is implemented in <name>_command.cpp.
constexpr Subcommand kSubcommands[] = {
    {"version", "version", printVersion},
    {"info", "info MESH [--no-repair] [--weld-tolerance T]", runInfo},
    {"convert", "convert IN OUT [--repair]", runConvert},
    {"metrics", "metrics RESULT [--reference INPUT]", runMetrics},
    {"remesh",
     "remesh IN -o OUT [--edge-length h | --vertices K] [--rosy 6|4] [--sizing uniform|curvature] "
     "[--placement balanced|on_surface] [--feature-angle DEG] [--d-sing X] [--hex OUT_HEX] "
     "[--textured OUT_OBJ] [--metrics METRICS.json] [--quiet]",
     runRemesh},
    {"field",
     "field MESH [--rosy 6|4] [--d-sing X] [--max-merged-index K] [--no-clustering] "
     "[--free-boundary] [-o FIELD.ply]",
     runField},
    {"param",
     "param MESH -o TEXTURED.obj [--edge-length h | --vertices K] [--rosy 6|4] "
     "[--sizing uniform|curvature] [--texture HEX.png] [--rounding direct|greedy] [--d-sing X] "
     "[--feature-angle DEG]",
     runParam},
};

int printUsage(std::ostream& out) {
  out << "usage: hexcover <command> [arguments]\n\ncommands:\n";
  for (const auto& sub : kSubcommands) out << "  " << sub.synopsis << "\n";
  return 2;
}

/// Whether the subcommand's arguments ask for its usage (--help or -h anywhere among them).
bool asksForHelp(int argc, char** argv) {
  for (int k = 2; k < argc; ++k)
    if (std::strcmp(argv[k], "--help") == 0 || std::strcmp(argv[k], "-h") == 0) return true;
  return false;
}

}  // namespace
}  // namespace hexcover::cli

int main(int argc, char** argv) {
  using namespace hexcover::cli;
  hexcover::keepFreedMemoryForReuse();
  if (argc < 2) return printUsage(std::cerr);
  const std::string_view name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    printUsage(std::cout);
    return 0;
  }
  for (const auto& sub : kSubcommands) {
    if (sub.name != name) continue;
    if (asksForHelp(argc, argv)) {
      std::cout << "usage: hexcover " << sub.synopsis << "\n";
      return 0;
    }
    try {
      return sub.run(argc, argv);
    } catch (const UsageError& e) {
      std::cerr << "hexcover " << name << ": " << e.what() << "\nusage: hexcover " << sub.synopsis
                << "\n";
      return 2;
    } catch (const hexcover::Error& e) {
      std::cerr << "hexcover " << name << ": " << e.what() << "\n";
      return 1;
    } catch (const std::exception& e) {
      std::cerr << "hexcover " << name << ": internal error: " << e.what() << "\n";
      return 1;
    }
  }
  std::cerr << "hexcover: unknown command '" << name << "'\n";
  return printUsage(std::cerr);
}
