// `hexcover info MESH [--no-repair] [--weld-tolerance T]`: the validation and repair report of a
// mesh file as one JSON object on stdout.

#include <iostream>

#include "api/mesh_report_json.h"
#include "clients/cli/arguments.h"
#include "clients/cli/commands.h"
#include "core/mesh/load.h"
#include "core/mesh/validate.h"

namespace hexcover::cli {

int runInfo(int argc, char** argv) {
  const Arguments args(argc, argv, 2, {"--weld-tolerance"}, {"--no-repair"});
  const std::string& path = args.positional(0, "MESH");
  args.expectPositionalCount(1);
  RepairOptions options;
  if (const auto tolerance = args.number("--weld-tolerance")) options.weldTolerance = *tolerance;

  const MeshReport report = args.has("--no-repair") ? validateMesh(readMesh(path))
                                                    : loadRepairedMesh(path, {}, options).report;
  nlohmann::json json = {{"file", path}};
  json.update(toJson(report));
  std::cout << json.dump(2) << "\n";
  return 0;
}

}  // namespace hexcover::cli
