#include "server/upload.h"

#include <algorithm>
#include <stdexcept>

namespace hexcover::server {

Sha256::Sha256() : context_(EVP_MD_CTX_new(), EVP_MD_CTX_free) {
  if (!context_ || EVP_DigestInit_ex(context_.get(), EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("SHA-256 is unavailable");
}

void Sha256::update(const void* data, std::size_t size) {
  EVP_DigestUpdate(context_.get(), data, size);
}

std::string Sha256::hex() {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  EVP_DigestFinal_ex(context_.get(), digest, &length);
  static constexpr char kHex[] = "0123456789abcdef";
  std::string text;
  for (unsigned int i = 0; i < length; ++i) {
    text += kHex[digest[i] >> 4];
    text += kHex[digest[i] & 15];
  }
  return text;
}

UploadFile::UploadFile(std::filesystem::path path, std::uint64_t limit)
    : path_(std::move(path)), limit_(limit), file_(std::fopen(path_.c_str(), "wb")) {
  if (!file_) throw std::runtime_error("cannot create upload file " + path_.string());
}

UploadFile::~UploadFile() {
  if (file_) std::fclose(file_);
  if (!released_) {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
}

bool UploadFile::append(const char* data, std::size_t size) {
  bytes_ += size;
  if (overLimit() || writeFailed_) return false;
  if (head_.size() < kHeadBytes) head_.append(data, std::min(size, kHeadBytes - head_.size()));
  hash_.update(data, size);
  if (std::fwrite(data, 1, size, file_) != size) writeFailed_ = true;
  return !writeFailed_;
}

bool UploadFile::finish() {
  if (!file_) return !writeFailed_;
  if (std::fclose(file_) != 0) writeFailed_ = true;
  file_ = nullptr;
  return !writeFailed_;
}

}  // namespace hexcover::server
