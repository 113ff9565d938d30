// Mesh writers (writeMesh in io.h). Output goes through a fixed-size buffer straight to the file,
// so writing a multi-million-face mesh never builds the whole file in memory.

#include <array>
#include <bit>
#include <charconv>
#include <cstdio>
#include <memory>
#include <string>

#include "core/common/error.h"
#include "core/mesh/io.h"
#include "core/mesh/soup_connectivity.h"

namespace hexcover {
namespace {

// Buffered binary/text output to a file; write errors surface as Error(Io) in finish().
class OutputFile {
 public:
  explicit OutputFile(const std::filesystem::path& path)
      : path_(path), file_(std::fopen(path.c_str(), "wb")) {
    if (!file_)
      throw Error(ErrorCode::Io, "cannot create '" + path.string() + "': " + std::strerror(errno));
  }
  ~OutputFile() {
    if (file_) std::fclose(file_);
  }
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  void write(std::string_view text) {
    if (text.size() > kCapacity - used_) flush();
    if (text.size() > kCapacity) {
      ok_ = ok_ && std::fwrite(text.data(), 1, text.size(), file_) == text.size();
      return;
    }
    std::memcpy(buffer_.get() + used_, text.data(), text.size());
    used_ += text.size();
  }
  void write(char c) { write(std::string_view(&c, 1)); }
  /// Shortest decimal text that reads back as the same double.
  void number(double x) {
    char text[32];
    const auto result = std::to_chars(text, text + sizeof text, x);
    write(std::string_view(text, static_cast<std::size_t>(result.ptr - text)));
  }
  void number(std::uint64_t x) {
    char text[24];
    const auto result = std::to_chars(text, text + sizeof text, x);
    write(std::string_view(text, static_cast<std::size_t>(result.ptr - text)));
  }
  template <typename T>
  void littleEndian(T value) {
    using Bits = std::conditional_t<
        sizeof(T) == 8, std::uint64_t,
        std::conditional_t<sizeof(T) == 4, std::uint32_t,
                           std::conditional_t<sizeof(T) == 2, std::uint16_t, std::uint8_t>>>;
    const auto bits = std::bit_cast<Bits>(value);
    char bytes[sizeof(T)];
    for (std::size_t i = 0; i < sizeof(T); ++i)
      bytes[i] = static_cast<char>((bits >> (8 * i)) & 0xffu);
    write(std::string_view(bytes, sizeof(T)));
  }
  void finish() {
    flush();
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!ok_ || !closed) throw Error(ErrorCode::Io, "cannot write '" + path_.string() + "'");
  }

 private:
  static constexpr std::size_t kCapacity = 1 << 20;
  void flush() {
    ok_ = ok_ && std::fwrite(buffer_.get(), 1, used_, file_) == used_;
    used_ = 0;
  }
  std::filesystem::path path_;
  std::FILE* file_;
  std::unique_ptr<char[]> buffer_ = std::make_unique<char[]>(kCapacity);
  std::size_t used_ = 0;
  bool ok_ = true;
};

/// "x y z\n" of a point, shared by the OBJ and OFF vertex lines.
void writeCoordinates(OutputFile& out, const Eigen::Vector3d& p) {
  out.number(p.x());
  out.write(' ');
  out.number(p.y());
  out.write(' ');
  out.number(p.z());
  out.write('\n');
}

void writeObj(const PolygonSoup& soup, OutputFile& out) {
  out.write("# written by hexcover\n");
  for (const auto& p : soup.positions) {
    out.write("v ");
    writeCoordinates(out, p);
  }
  const bool textured = !soup.cornerTexcoords.empty();
  for (const auto& uv : soup.cornerTexcoords) {
    out.write("vt ");
    out.number(uv.x());
    out.write(' ');
    out.number(uv.y());
    out.write('\n');
  }
  for (std::size_t f = 0; f < soup.faceCount(); ++f) {
    out.write('f');
    for (std::size_t c = soup.faceStarts[f]; c < soup.faceStarts[f + 1]; ++c) {
      out.write(' ');
      out.number(std::uint64_t{soup.cornerVertices[c]} + 1);
      if (textured) {
        out.write('/');
        out.number(std::uint64_t{c} + 1);
      }
    }
    out.write('\n');
  }
}

void writeOff(const PolygonSoup& soup, OutputFile& out) {
  out.write("OFF\n");
  out.number(std::uint64_t{soup.vertexCount()});
  out.write(' ');
  out.number(std::uint64_t{soup.faceCount()});
  out.write(" 0\n");
  for (const auto& p : soup.positions) {
    writeCoordinates(out, p);
  }
  for (std::size_t f = 0; f < soup.faceCount(); ++f) {
    out.number(std::uint64_t{soup.faceSize(f)});
    for (std::size_t c = soup.faceStarts[f]; c < soup.faceStarts[f + 1]; ++c) {
      out.write(' ');
      out.number(std::uint64_t{soup.cornerVertices[c]});
    }
    out.write('\n');
  }
}

void writePly(const PolygonSoup& soup, OutputFile& out) {
  std::size_t largest = 0;
  for (std::size_t f = 0; f < soup.faceCount(); ++f) largest = std::max(largest, soup.faceSize(f));
  const bool byteCounts = largest <= 255;
  out.write("ply\nformat binary_little_endian 1.0\ncomment written by hexcover\nelement vertex ");
  out.number(std::uint64_t{soup.vertexCount()});
  out.write("\nproperty double x\nproperty double y\nproperty double z\nelement face ");
  out.number(std::uint64_t{soup.faceCount()});
  out.write(byteCounts ? "\nproperty list uchar int vertex_indices\nend_header\n"
                       : "\nproperty list uint int vertex_indices\nend_header\n");
  for (const auto& p : soup.positions)
    for (int i = 0; i < 3; ++i) out.littleEndian(p[i]);
  for (std::size_t f = 0; f < soup.faceCount(); ++f) {
    if (byteCounts)
      out.littleEndian(static_cast<std::uint8_t>(soup.faceSize(f)));
    else
      out.littleEndian(static_cast<std::uint32_t>(soup.faceSize(f)));
    for (std::size_t c = soup.faceStarts[f]; c < soup.faceStarts[f + 1]; ++c)
      out.littleEndian(static_cast<std::int32_t>(soup.cornerVertices[c]));
  }
}

void writeStl(const PolygonSoup& soup, OutputFile& out) {
  const std::uint64_t triangles = soup.triangleCount();
  if (triangles > UINT32_MAX)
    throw Error(ErrorCode::LimitExceeded, "too many triangles for binary STL");
  // The header must not start with "solid", or readers could take the file for ASCII.
  std::array<char, 80> header{};
  constexpr std::string_view kHeader = "binary STL written by hexcover";
  std::copy(kHeader.begin(), kHeader.end(), header.begin());
  out.write(std::string_view(header.data(), header.size()));
  out.littleEndian(static_cast<std::uint32_t>(triangles));
  for (std::size_t f = 0; f < soup.faceCount(); ++f) {
    const std::uint32_t* corners = soup.cornerVertices.data() + soup.faceStarts[f];
    for (std::size_t i = 1; i + 1 < soup.faceSize(f); ++i) {
      const Eigen::Vector3d& a = soup.positions[corners[0]];
      const Eigen::Vector3d& b = soup.positions[corners[i]];
      const Eigen::Vector3d& c = soup.positions[corners[i + 1]];
      const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
      for (const Eigen::Vector3d& p :
           {normal.allFinite() ? normal : Eigen::Vector3d::Zero().eval(), a, b, c})
        for (int k = 0; k < 3; ++k) out.littleEndian(static_cast<float>(p[k]));
      out.littleEndian(std::uint16_t{0});
    }
  }
}

}  // namespace

void writeMesh(const PolygonSoup& soup, const std::filesystem::path& path) {
  const MeshFormat format = formatFromExtension(path);
  detail::checkSoupStructure(soup, /*checkIndices=*/true);
  OutputFile out(path);
  switch (format) {
    case MeshFormat::Obj:
      writeObj(soup, out);
      break;
    case MeshFormat::Off:
      writeOff(soup, out);
      break;
    case MeshFormat::Ply:
      writePly(soup, out);
      break;
    case MeshFormat::Stl:
      writeStl(soup, out);
      break;
  }
  out.finish();
}

}  // namespace hexcover
