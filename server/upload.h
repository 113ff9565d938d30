#pragma once
// Receiving an upload: bytes go straight to a file (never held whole in memory), counted
// against the size limit whatever the framing (Content-Length, chunked, multipart), hashed for
// idempotent replays, with the first bytes kept for format detection.

#include <openssl/evp.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

namespace hexcover::server {

/// SHA-256, fed incrementally; hex digest.
class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t size);
  void update(std::string_view text) { update(text.data(), text.size()); }
  /// Lowercase hex of the digest; the object cannot be fed afterwards.
  std::string hex();

 private:
  std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)> context_;
};

class UploadFile {
 public:
  /// Bytes of the upload kept in memory for format detection.
  static constexpr std::size_t kHeadBytes = 4096;

  /// Creates `path` for writing. Throws std::runtime_error when it cannot.
  UploadFile(std::filesystem::path path, std::uint64_t limit);
  /// Removes the file unless release() was called.
  ~UploadFile();
  UploadFile(const UploadFile&) = delete;
  UploadFile& operator=(const UploadFile&) = delete;

  /// Appends bytes. Returns false once the total went over the limit (nothing more is written)
  /// or the disk write failed; the bytes are still counted.
  bool append(const char* data, std::size_t size);
  /// Flushes and closes the file; false when the final write failed.
  bool finish();

  std::uint64_t bytes() const { return bytes_; }
  bool overLimit() const { return bytes_ > limit_; }
  bool writeFailed() const { return writeFailed_; }
  const std::string& head() const { return head_; }
  /// SHA-256 hex of the bytes received (call once, after finish()).
  std::string digest() { return hash_.hex(); }
  const std::filesystem::path& path() const { return path_; }
  /// Keeps the file on destruction (it was moved into a job).
  void release() { released_ = true; }

 private:
  std::filesystem::path path_;
  std::uint64_t limit_;
  std::FILE* file_ = nullptr;
  std::uint64_t bytes_ = 0;
  std::string head_;
  Sha256 hash_;
  bool writeFailed_ = false;
  bool released_ = false;
};

}  // namespace hexcover::server
