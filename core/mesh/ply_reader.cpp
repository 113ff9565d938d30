// PLY reader: ASCII, binary little and big endian; any vertex properties (x, y, z of any scalar
// type are kept), face lists of any size with any count and index type, `tristrips` elements
// (-1 restarts the strip), other elements skipped, CRLF header lines.

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>
#include <vector>

#include "core/mesh/mesh_readers.h"
#include "core/mesh/text_scanner.h"

namespace hexcover::detail {
namespace {

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };

bool parseScalar(std::string_view name, Scalar& type) {
  struct Name {
    std::string_view name;
    Scalar type;
  };
  static constexpr Name kNames[] = {
      {"char", Scalar::Int8},       {"int8", Scalar::Int8},      {"uchar", Scalar::UInt8},
      {"uint8", Scalar::UInt8},     {"short", Scalar::Int16},    {"int16", Scalar::Int16},
      {"ushort", Scalar::UInt16},   {"uint16", Scalar::UInt16},  {"int", Scalar::Int32},
      {"int32", Scalar::Int32},     {"uint", Scalar::UInt32},    {"uint32", Scalar::UInt32},
      {"int64", Scalar::Int64},     {"uint64", Scalar::UInt64},  {"float", Scalar::Float32},
      {"float32", Scalar::Float32}, {"double", Scalar::Float64}, {"float64", Scalar::Float64}};
  for (const auto& entry : kNames)
    if (entry.name == name) {
      type = entry.type;
      return true;
    }
  return false;
}

std::size_t byteSize(Scalar type) {
  switch (type) {
    case Scalar::Int8:
    case Scalar::UInt8:
      return 1;
    case Scalar::Int16:
    case Scalar::UInt16:
      return 2;
    case Scalar::Int32:
    case Scalar::UInt32:
    case Scalar::Float32:
      return 4;
    case Scalar::Int64:
    case Scalar::UInt64:
    case Scalar::Float64:
      return 8;
  }
  return 1;
}

bool isFloating(Scalar type) { return type == Scalar::Float32 || type == Scalar::Float64; }

struct Property {
  std::string name;
  Scalar type = Scalar::Float32;  ///< value type (item type of a list)
  bool isList = false;
  Scalar countType = Scalar::UInt8;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
  std::size_t line = 0;  ///< header line that declares it
};

enum class Encoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct Header {
  Encoding encoding = Encoding::Ascii;
  std::vector<Element> elements;
  std::size_t dataOffset = 0;
  std::size_t lines = 0;
};

[[noreturn]] void failHeader(std::size_t line, const std::string& what) {
  failAtLine(ErrorCode::MalformedInput, "PLY header", line, what);
}

Header parseHeader(std::string_view bytes) {
  Header header;
  LineScanner lines(bytes);
  std::string_view line;
  if (!lines.next(line) || line != "ply") failHeader(1, "the file must start with the line 'ply'");
  bool formatSeen = false;
  for (;;) {
    if (!lines.next(line)) failHeader(lines.lineNumber(), "no 'end_header' line");
    LineTokens tokens(line);
    const std::string_view keyword = tokens.next();
    const std::size_t lineNumber = lines.lineNumber();
    if (keyword == "end_header") break;
    if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      const std::string_view encoding = tokens.next();
      if (encoding == "ascii")
        header.encoding = Encoding::Ascii;
      else if (encoding == "binary_little_endian")
        header.encoding = Encoding::BinaryLittleEndian;
      else if (encoding == "binary_big_endian")
        header.encoding = Encoding::BinaryBigEndian;
      else
        failHeader(lineNumber, "unknown format " + quoted(encoding));
      formatSeen = true;
    } else if (keyword == "element") {
      Element element;
      element.name = std::string(tokens.next());
      element.line = lineNumber;
      std::int64_t count = -1;
      if (element.name.empty() || !parseInteger(tokens.next(), count) || count < 0)
        failHeader(lineNumber, "expected 'element <name> <count>'");
      element.count = static_cast<std::uint64_t>(count);
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) failHeader(lineNumber, "property before any element");
      Property property;
      std::string_view type = tokens.next();
      if (type == "list") {
        property.isList = true;
        if (!parseScalar(tokens.next(), property.countType) || isFloating(property.countType))
          failHeader(lineNumber, "a list needs an integer count type");
        type = tokens.next();
      }
      if (!parseScalar(type, property.type))
        failHeader(lineNumber, "unknown property type " + quoted(type));
      property.name = std::string(tokens.next());
      if (property.name.empty()) failHeader(lineNumber, "property without a name");
      header.elements.back().properties.push_back(std::move(property));
    } else {
      failHeader(lineNumber, "unknown header keyword " + quoted(keyword));
    }
  }
  if (!formatSeen) failHeader(lines.lineNumber(), "no 'format' line");
  header.dataOffset = lines.offset();
  header.lines = lines.lineNumber();
  return header;
}

// ASCII body: whitespace-separated values across lines.
class AsciiValues {
 public:
  AsciiValues(std::string_view bytes, std::size_t offset, std::size_t firstLine)
      : body_(bytes.substr(std::min(offset, bytes.size()))), lines_(body_), firstLine_(firstLine) {}
  double real(Scalar) { return parse(); }
  std::int64_t integer(Scalar type) {
    const double value = parse();
    if (value != std::floor(value) || std::abs(value) > 9.0e15)
      fail("expected an integer value for a " + std::string(isFloating(type) ? "real" : "integer") +
           " property");
    return static_cast<std::int64_t>(value);
  }
  /// Skips n values of `type` (ASCII: n tokens).
  void skip(Scalar type, std::uint64_t n) {
    for (std::uint64_t i = 0; i < n; ++i) real(type);
  }
  /// An upper bound of the bytes left (the whole body), for bounding reservations.
  std::uint64_t remaining() const { return body_.size(); }
  [[noreturn]] void fail(const std::string& what) {
    failAtLine(ErrorCode::MalformedInput, "PLY", firstLine_ + lines_.lineNumber(), what);
  }
  std::string location() const {
    return "line " + std::to_string(firstLine_ + lines_.lineNumber());
  }

 private:
  double parse() {
    std::string_view token;
    while ((token = tokens_.next()).empty()) {
      std::string_view line;
      if (!lines_.next(line)) fail("the data ends early (truncated file)");
      tokens_ = LineTokens(line);
    }
    double value = 0;
    if (!parseDouble(token, value)) fail("expected a number, got " + quoted(token));
    return value;
  }
  std::string_view body_;
  LineScanner lines_;
  LineTokens tokens_{{}};
  std::size_t firstLine_;
};

// Binary body in either byte order.
class BinaryValues {
 public:
  BinaryValues(std::string_view bytes, std::size_t offset, bool bigEndian)
      : bytes_(bytes), pos_(std::min(offset, bytes.size())), bigEndian_(bigEndian) {}
  double real(Scalar type) {
    const std::uint64_t raw = take(byteSize(type));
    switch (type) {
      case Scalar::Float32:
        return std::bit_cast<float>(static_cast<std::uint32_t>(raw));
      case Scalar::Float64:
        return std::bit_cast<double>(raw);
      default:
        return static_cast<double>(signExtend(raw, type));
    }
  }
  std::int64_t integer(Scalar type) {
    if (!isFloating(type)) return signExtend(take(byteSize(type)), type);
    const double value = real(type);
    if (!(value == std::floor(value)) || std::abs(value) > 9.0e15)
      fail("expected an integer value");
    return static_cast<std::int64_t>(value);
  }
  void skip(Scalar type, std::uint64_t n) { skipBytes(n * byteSize(type)); }
  void skipBytes(std::uint64_t n) {
    if (n > remaining()) truncated(n);
    pos_ += n;
  }
  std::uint64_t remaining() const { return bytes_.size() - pos_; }
  [[noreturn]] void fail(const std::string& what) {
    throw Error(ErrorCode::MalformedInput, "PLY byte offset " + std::to_string(pos_) + ": " + what);
  }
  std::string location() const { return "byte offset " + std::to_string(pos_); }

 private:
  [[noreturn]] void truncated(std::uint64_t needed) {
    fail("truncated binary data: " + std::to_string(needed) + " more bytes needed, " +
         std::to_string(remaining()) + " left");
  }
  std::uint64_t take(std::size_t n) {
    if (n > remaining()) truncated(n);
    std::uint64_t value = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const auto byte = static_cast<unsigned char>(bytes_[pos_ + (bigEndian_ ? i : n - 1 - i)]);
      value = value << 8 | byte;
    }
    pos_ += n;
    return value;
  }
  static std::int64_t signExtend(std::uint64_t raw, Scalar type) {
    switch (type) {
      case Scalar::Int8:
        return static_cast<std::int8_t>(raw);
      case Scalar::Int16:
        return static_cast<std::int16_t>(raw);
      case Scalar::Int32:
        return static_cast<std::int32_t>(raw);
      case Scalar::Int64:
        return static_cast<std::int64_t>(raw);
      case Scalar::UInt64:
        return raw > static_cast<std::uint64_t>(INT64_MAX) ? -1 : static_cast<std::int64_t>(raw);
      default:
        return static_cast<std::int64_t>(raw);
    }
  }
  std::string_view bytes_;
  std::size_t pos_;
  bool bigEndian_;
};

const Property* findProperty(const Element& element, std::initializer_list<std::string_view> names,
                             bool list) {
  for (const auto name : names)
    for (const auto& p : element.properties)
      if (p.name == name && p.isList == list) return &p;
  return nullptr;
}

template <typename Values>
std::uint64_t readListCount(Values& values, const Property& property, std::uint64_t limit) {
  const std::int64_t n = values.integer(property.countType);
  if (n < 0)
    values.fail("negative list length " + std::to_string(n) + " in property '" + property.name +
                "'");
  if (static_cast<std::uint64_t>(n) > limit)
    values.fail("list length " + std::to_string(n) + " in property '" + property.name +
                "' exceeds the data left (truncated or corrupt data)");
  return static_cast<std::uint64_t>(n);
}

template <typename Values>
void skipProperty(Values& values, const Property& property) {
  if (!property.isList) return values.skip(property.type, 1);
  values.skip(property.type,
              readListCount(values, property, values.remaining() / byteSize(property.type)));
}

template <typename Values>
void readVertices(Values& values, const Element& element, PolygonSoup& soup) {
  const Property* axes[3] = {findProperty(element, {"x"}, false),
                             findProperty(element, {"y"}, false),
                             findProperty(element, {"z"}, false)};
  if (!axes[0] || !axes[1] || !axes[2])
    failAtLine(ErrorCode::MalformedInput, "PLY header", element.line,
               "the vertex element has no x, y and z properties");
  soup.positions.reserve(soup.positions.size() +
                         std::min<std::uint64_t>(element.count, values.remaining() / 6));
  for (std::uint64_t v = 0; v < element.count; ++v) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    // Binary data is located by where the record starts, text by the line it was read from.
    std::string where = values.location();
    for (const auto& property : element.properties) {
      const int axis = &property == axes[0]   ? 0
                       : &property == axes[1] ? 1
                       : &property == axes[2] ? 2
                                              : -1;
      if (axis < 0)
        skipProperty(values, property);
      else
        p[axis] = values.real(property.type);
    }
    if constexpr (std::is_same_v<Values, AsciiValues>) where = values.location();
    if (!p.allFinite())
      throw Error(ErrorCode::InvalidMesh, "PLY " + where + ": vertex " + std::to_string(v) +
                                              " has a NaN or infinite coordinate");
    soup.positions.push_back(p);
  }
}

// Reads the indices of one list into `out`, checking them against the declared vertex count.
template <typename Values>
void readIndices(Values& values, const Property& list, std::uint64_t vertexCount, bool allowRestart,
                 std::vector<std::int64_t>& out) {
  const std::uint64_t n = readListCount(values, list, values.remaining() / byteSize(list.type));
  out.clear();
  for (std::uint64_t i = 0; i < n; ++i) {
    const std::int64_t index = values.integer(list.type);
    if ((index < 0 && !(allowRestart && index == -1)) ||
        (index >= 0 && static_cast<std::uint64_t>(index) >= vertexCount))
      values.fail("vertex index " + std::to_string(index) + " is out of range (the file has " +
                  std::to_string(vertexCount) + " vertices)");
    out.push_back(index);
  }
}

template <typename Values>
void readFaces(Values& values, const Element& element, std::uint64_t vertexCount,
               const ReadOptions& options, PolygonSoup& soup) {
  const Property* list = findProperty(element, {"vertex_indices", "vertex_index"}, true);
  if (!list)
    failAtLine(ErrorCode::MalformedInput, "PLY header", element.line,
               "the face element has no vertex_indices list");
  std::vector<std::int64_t> indices;
  for (std::uint64_t f = 0; f < element.count; ++f) {
    if (soup.faceCount() >= options.maxFaces)
      throw Error(ErrorCode::LimitExceeded,
                  "PLY: more than " + std::to_string(options.maxFaces) + " faces");
    for (const auto& property : element.properties) {
      if (&property != list) {
        skipProperty(values, property);
        continue;
      }
      readIndices(values, property, vertexCount, false, indices);
      for (const auto index : indices)
        soup.cornerVertices.push_back(static_cast<std::uint32_t>(index));
      soup.faceStarts.push_back(static_cast<std::uint32_t>(soup.cornerVertices.size()));
    }
  }
}

// Triangle strips: within a strip, triangle i is (s[i], s[i+1], s[i+2]) with every other one
// reversed to keep the orientation; -1 starts a new strip. Triangles with a repeated index are
// the strip's turning devices, not faces, and are skipped.
template <typename Values>
void readTriangleStrips(Values& values, const Element& element, std::uint64_t vertexCount,
                        const ReadOptions& options, PolygonSoup& soup) {
  const Property* list = findProperty(element, {"vertex_indices", "vertex_index"}, true);
  if (!list)
    failAtLine(ErrorCode::MalformedInput, "PLY header", element.line,
               "the tristrips element has no vertex_indices list");
  std::vector<std::int64_t> indices;
  for (std::uint64_t s = 0; s < element.count; ++s) {
    for (const auto& property : element.properties) {
      if (&property != list) {
        skipProperty(values, property);
        continue;
      }
      readIndices(values, property, vertexCount, true, indices);
      std::size_t stripStart = 0;
      for (std::size_t i = 0; i < indices.size(); ++i) {
        if (indices[i] < 0) {
          stripStart = i + 1;
          continue;
        }
        if (i < stripStart + 2) continue;
        const std::size_t k = i - stripStart;  // position in the strip
        std::array<std::int64_t, 3> t = {indices[i - 2], indices[i - 1], indices[i]};
        if (k % 2 == 1) std::swap(t[0], t[1]);
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
        if (soup.faceCount() >= options.maxFaces)
          throw Error(ErrorCode::LimitExceeded,
                      "PLY: more than " + std::to_string(options.maxFaces) + " faces");
        for (const auto v : t) soup.cornerVertices.push_back(static_cast<std::uint32_t>(v));
        soup.faceStarts.push_back(static_cast<std::uint32_t>(soup.cornerVertices.size()));
      }
    }
  }
}

template <typename Values>
void skipElement(Values& values, const Element& element) {
  if (element.properties.empty()) return;
  const bool fixedSize = std::none_of(element.properties.begin(), element.properties.end(),
                                      [](const Property& p) { return p.isList; });
  if constexpr (std::is_same_v<Values, BinaryValues>) {
    if (fixedSize) {
      std::uint64_t recordBytes = 0;
      for (const auto& p : element.properties) recordBytes += byteSize(p.type);
      if (element.count > values.remaining() / recordBytes)
        values.fail("truncated binary data: element '" + element.name + "' needs " +
                    std::to_string(element.count) + " records of " + std::to_string(recordBytes) +
                    " bytes");
      return values.skipBytes(element.count * recordBytes);
    }
  }
  for (std::uint64_t r = 0; r < element.count; ++r)
    for (const auto& property : element.properties) skipProperty(values, property);
}

template <typename Values>
PolygonSoup readBody(Values& values, const Header& header, const ReadOptions& options) {
  std::uint64_t vertexCount = 0;
  for (const auto& element : header.elements) {
    if (element.name == "vertex") vertexCount += element.count;
    if (element.name == "vertex" && element.count > options.maxVertices)
      throw Error(ErrorCode::LimitExceeded, "PLY header line " + std::to_string(element.line) +
                                                ": declares " + std::to_string(element.count) +
                                                " vertices, over the limit of " +
                                                std::to_string(options.maxVertices));
    if (element.name == "face" && element.count > options.maxFaces)
      throw Error(ErrorCode::LimitExceeded, "PLY header line " + std::to_string(element.line) +
                                                ": declares " + std::to_string(element.count) +
                                                " faces, over the limit of " +
                                                std::to_string(options.maxFaces));
  }
  PolygonSoup soup;
  for (const auto& element : header.elements) {
    if (element.name == "vertex")
      readVertices(values, element, soup);
    else if (element.name == "face")
      readFaces(values, element, vertexCount, options, soup);
    else if (element.name == "tristrips")
      readTriangleStrips(values, element, vertexCount, options, soup);
    else
      skipElement(values, element);
  }
  return soup;
}

}  // namespace

PolygonSoup parsePly(std::string_view bytes, const ReadOptions& options) {
  const Header header = parseHeader(bytes);
  if (header.encoding == Encoding::Ascii) {
    AsciiValues values(bytes, header.dataOffset, header.lines);
    return readBody(values, header, options);
  }
  BinaryValues values(bytes, header.dataOffset, header.encoding == Encoding::BinaryBigEndian);
  return readBody(values, header, options);
}

}  // namespace hexcover::detail
