#pragma once
// A stand-in for the geometry engine in the server's unit tests (the end-to-end suite, e2e_*,
// runs the real binary). The mesh text steers it: a body containing "refuse" is refused by
// validation, "throw" raises an unexpected exception; otherwise the run waits while the gate is
// closed (checking for cancellation), then "remeshes" by copying the input.

#include <atomic>
#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include "server/engine.h"

namespace hexcover::server::test {

class StubEngine final : public Engine {
 public:
  /// While closed, runs wait (and can be canceled).
  std::atomic<bool> gateOpen{true};
  /// Runs started so far.
  mutable std::atomic<int> runs{0};

  nlohmann::json normalizeOptions(const nlohmann::json& requested) const override {
    nlohmann::json normalized = {{"edge_length", nullptr}, {"rosy", 6}};
    for (const auto& [name, value] : requested.items()) {
      if (name == "edge_length" && value.is_number() && value.get<double>() > 0.0)
        normalized[name] = value;
      else if (name == "rosy" && (value == 4 || value == 6))
        normalized[name] = value;
      else
        throw Error(ErrorCode::InvalidOption, "option '" + name + "' is invalid: " + value.dump());
    }
    return normalized;
  }

  std::string detectFormat(std::string_view head) const override {
    if (head.rfind("OFF", 0) == 0) return "off";
    if (head.rfind("v ", 0) == 0 || head.rfind("#", 0) == 0) return "obj";
    throw Error(ErrorCode::UnknownFormat, "the bytes are not OBJ or OFF");
  }

  JobOutcome run(const JobInput& input, const RunContext& context) const override {
    ++runs;
    std::ifstream in(input.meshFile, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    const std::string mesh = text.str();
    if (mesh.find("refuse") != std::string::npos)
      throw RefusedInput(Error(ErrorCode::InvalidMesh, "the mesh has 1 non-manifold edge"),
                         {{"input", {{"non_manifold_edges", 1}}}});
    if (mesh.find("throw") != std::string::npos)
      throw std::runtime_error("secret internal detail at 0xdeadbeef");
    // "# peak N": the run announces a peak memory of N MiB, as the pipeline does.
    if (const auto at = mesh.find("# peak "); at != std::string::npos)
      context.reservePeakMemory(std::stod(mesh.substr(at + 7)));
    while (!gateOpen) {
      context.report("stub", 0.5);
      context.throwIfCanceled();
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    context.throwIfCanceled();
    context.report("stub", 1.0);
    std::ofstream(input.outputDir / "triangles.obj", std::ios::binary) << mesh;
    std::size_t faces = 0;
    for (std::size_t at = mesh.find("\nf "); at != std::string::npos;
         at = mesh.find("\nf ", at + 1))
      ++faces;
    return {{{"input", {{"faces", faces}}}},
            {{"faces", faces}, {"options", input.options}},
            {{"triangles", "obj", "triangles.obj", 0}}};
  }
};

}  // namespace hexcover::server::test
