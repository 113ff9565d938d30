// `hexcover convert IN OUT [--repair]`: reads a mesh in any supported format and writes it in the
// format of OUT's extension. Polygons are kept unless --repair asks for the repaired triangle mesh.

#include <iostream>

#include "clients/cli/arguments.h"
#include "clients/cli/commands.h"
#include "core/mesh/io.h"
#include "core/mesh/repair.h"

namespace hexcover::cli {

int runConvert(int argc, char** argv) {
  const Arguments args(argc, argv, 2, {}, {"--repair"});
  const std::string& input = args.positional(0, "IN");
  const std::string& output = args.positional(1, "OUT");
  args.expectPositionalCount(2);
  formatFromExtension(output);  // refuse an unknown output extension before reading
  const PolygonSoup soup = readMesh(input);
  writeMesh(args.has("--repair") ? toPolygonSoup(repairMesh(soup).mesh) : soup, output);
  return 0;
}

}  // namespace hexcover::cli
