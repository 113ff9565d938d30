#include "server/web_assets.h"

#include <httplib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace hexcover::server {
namespace {

std::string_view contentTypeOf(const std::filesystem::path& file) {
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 12> kTypes{{
      {".html", "text/html; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},
      {".svg", "image/svg+xml"},
      {".png", "image/png"},
      {".jpg", "image/jpeg"},
      {".ico", "image/x-icon"},
      {".wasm", "application/wasm"},
      {".txt", "text/plain; charset=utf-8"},
      {"", "text/plain; charset=utf-8"},  // LICENSE and other extension-less notices
  }};
  const std::string extension = file.extension().string();
  for (const auto& [ext, type] : kTypes) {
    if (ext == extension) return type;
  }
  return "application/octet-stream";
}

/// URL path segments we serve: no hidden files, nothing a URL would need to escape.
bool isServableName(const std::string& name) {
  return !name.empty() && name.front() != '.' &&
         std::all_of(name.begin(), name.end(), [](unsigned char c) {
           return std::isalnum(c) || c == '.' || c == '_' || c == '-';
         });
}

std::string escapeRegex(std::string_view text) {
  std::string escaped;
  for (const char c : text) {
    if (std::string_view("\\^$.|?*+()[]{}").find(c) != std::string_view::npos) escaped += '\\';
    escaped += c;
  }
  return escaped;
}

/// Streams `file` in 64 KiB chunks; 404 when it disappeared since the server started.
httplib::Server::Handler fileHandler(std::filesystem::path file) {
  return [file = std::move(file)](const httplib::Request&, httplib::Response& res) {
    std::error_code error;
    const auto size = std::filesystem::file_size(file, error);
    auto stream = std::make_shared<std::ifstream>(file, std::ios::binary);
    if (error || !*stream) {
      res.status = 404;
      return;
    }
    res.set_header("Cache-Control", "no-cache");
    res.set_header("X-Content-Type-Options", "nosniff");
    res.set_content_provider(
        static_cast<std::size_t>(size), std::string(contentTypeOf(file)),
        [stream](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
          std::vector<char> buffer(std::min<std::size_t>(length, 64 * 1024));
          stream->clear();
          stream->seekg(static_cast<std::streamoff>(offset));
          stream->read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
          const auto got = static_cast<std::size_t>(stream->gcount());
          return got > 0 && sink.write(buffer.data(), got);
        });
  };
}

}  // namespace

std::filesystem::path defaultWebRoot() {
  std::error_code error;
  const auto executable = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::filesystem::path("web") : executable.parent_path() / "web";
}

std::size_t mountWebAssets(httplib::Server& server, const std::filesystem::path& root) {
  std::error_code error;
  if (!std::filesystem::is_directory(root, error)) return 0;
  std::vector<std::pair<std::string, std::filesystem::path>> routes;  // URL path, file
  // Symbolic links are neither followed into folders nor served as files.
  for (auto it = std::filesystem::recursive_directory_iterator(root, error);
       !error && it != std::filesystem::recursive_directory_iterator(); it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (!isServableName(name)) {
      if (it->is_directory(error)) it.disable_recursion_pending();
      continue;
    }
    if (!it->is_regular_file(error) || it->is_symlink(error)) continue;
    routes.emplace_back("/" + it->path().lexically_relative(root).generic_string(), it->path());
  }
  if (const auto index = root / "index.html"; std::filesystem::is_regular_file(index, error)) {
    routes.emplace_back("/", index);
  }
  for (auto& [url, file] : routes) server.Get(escapeRegex(url), fileHandler(std::move(file)));
  return routes.size();
}

}  // namespace hexcover::server
