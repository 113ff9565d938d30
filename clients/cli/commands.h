#pragma once
// The subcommands of `hexcover`. Each returns the process exit status:
// 0 success, 1 bad input (one clear line on stderr), 2 bad usage.
// Each lives in its own <name>_command.cpp and is listed in main.cpp.

namespace hexcover::cli {

/// A subcommand: argv[0] is the program, argv[1] the subcommand name, arguments from argv[2].
using Command = int (*)(int argc, char** argv);

/// `hexcover info MESH`: validation and repair report as one JSON object (info_command.cpp).
int runInfo(int argc, char** argv);
/// `hexcover convert IN OUT`: format conversion, output format from the extension (convert_command.cpp).
int runConvert(int argc, char** argv);
/// `hexcover metrics RESULT [--reference INPUT]`: quality metrics as one JSON object
/// (metrics_command.cpp).
int runMetrics(int argc, char** argv);
/// `hexcover remesh IN -o OUT [...]`: the remeshing pipeline on one file (remesh_command.cpp).
int runRemesh(int argc, char** argv);
/// `hexcover field MESH [--rosy 6|4] [--d-sing X] [-o FIELD.ply]`: the N-RoSy field and its
/// singularities as one JSON object (field_command.cpp).
int runField(int argc, char** argv);
/// `hexcover param MESH -o TEXTURED.obj [...]`: the seamless parameterization, a textured mesh and
/// optionally the hexagonal pattern tile; one JSON object on stdout (param_command.cpp).
int runParam(int argc, char** argv);

}  // namespace hexcover::cli
