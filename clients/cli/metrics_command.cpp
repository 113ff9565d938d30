// `hexcover metrics RESULT [--reference INPUT]`: quality metrics of a mesh, and its distance
// and topology against a reference, as one JSON object on stdout.

#include <iostream>

#include "api/metrics_json.h"
#include "clients/cli/arguments.h"
#include "clients/cli/commands.h"
#include "core/mesh/load.h"
#include "core/metrics/metrics.h"

namespace hexcover::cli {

int runMetrics(int argc, char** argv) {
  const Arguments args(argc, argv, 2, {"--reference"}, {});
  const std::string& resultPath = args.positional(0, "RESULT");
  args.expectPositionalCount(1);
  const auto referencePath = args.value("--reference");

  const TriMesh result = loadMesh(resultPath);
  const std::optional<TriMesh> reference =
      referencePath ? std::optional<TriMesh>(loadMesh(*referencePath)) : std::nullopt;
  const QualityReport report = measureQuality(result, reference ? &*reference : nullptr);

  nlohmann::json json = {{"result", resultPath},
                         {"reference", referencePath ? nlohmann::json(*referencePath) : nullptr}};
  json.update(toJson(report));
  std::cout << json.dump(2) << "\n";
  return 0;
}

}  // namespace hexcover::cli
