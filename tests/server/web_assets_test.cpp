// server/web_assets: the web front-end's folder served at `/`, and nothing outside it.

#include "server/web_assets.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

namespace hexcover::server {
namespace {

namespace fs = std::filesystem;

void writeFile(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

class WebAssetsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    base_ = fs::temp_directory_path() /
            ("hexcover-web-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
             "-" + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    root_ = base_ / "web";
    writeFile(root_ / "index.html", "<!doctype html><title>hexcover</title>");
    writeFile(root_ / "app.js", "export const answer = 42;\n");
    writeFile(root_ / "vendor" / "three" / "three.module.js", std::string(300'000, 'x'));
    writeFile(root_ / ".secret", "hidden");
    writeFile(base_ / "outside.txt", "outside the web root");
    fs::create_symlink(base_ / "outside.txt", root_ / "link.txt");
    fs::create_directory_symlink(base_, root_ / "up");

    served_ = mountWebAssets(server_, root_);
    port_ = server_.bind_to_any_port("127.0.0.1");
    thread_ = std::thread([this] { server_.listen_after_bind(); });
    while (!server_.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }

  void TearDown() override {
    server_.stop();
    thread_.join();
    fs::remove_all(base_);
  }

  httplib::Result get(const std::string& path) {
    httplib::Client client("127.0.0.1", port_);
    return client.Get(path);
  }

  fs::path base_, root_;
  httplib::Server server_;
  std::size_t served_ = 0;
  int port_ = 0;
  std::thread thread_;
};

TEST_F(WebAssetsTest, ServesEveryRegularFileWithItsContentType) {
  EXPECT_EQ(served_, 4u);  // index.html (also as /), app.js, vendor/three/three.module.js
  const auto index = get("/");
  ASSERT_TRUE(index);
  EXPECT_EQ(index->status, 200);
  EXPECT_EQ(index->body, "<!doctype html><title>hexcover</title>");
  EXPECT_EQ(index->get_header_value("Content-Type"), "text/html; charset=utf-8");

  const auto script = get("/app.js");
  ASSERT_TRUE(script);
  EXPECT_EQ(script->status, 200);
  EXPECT_EQ(script->body, "export const answer = 42;\n");
  EXPECT_EQ(script->get_header_value("Content-Type"), "text/javascript; charset=utf-8");
  EXPECT_EQ(script->get_header_value("X-Content-Type-Options"), "nosniff");

  // Larger than one 64 KiB chunk: streamed in pieces, delivered whole.
  const auto large = get("/vendor/three/three.module.js");
  ASSERT_TRUE(large);
  EXPECT_EQ(large->status, 200);
  EXPECT_EQ(large->body, std::string(300'000, 'x'));
}

TEST_F(WebAssetsTest, NothingOutsideTheRootNorHiddenNorLinked) {
  for (const char* path : {"/../outside.txt", "/vendor/../../outside.txt", "/%2e%2e/outside.txt",
                           "/.secret", "/link.txt", "/up/outside.txt", "/vendor", "/vendor/",
                           "/missing.js", "/app.js/"}) {
    const auto res = get(path);
    ASSERT_TRUE(res) << path;
    EXPECT_EQ(res->status, 404) << path;
    EXPECT_EQ(res->body.find("outside the web root"), std::string::npos) << path;
  }
}

TEST_F(WebAssetsTest, OnlyGetAndHead) {
  httplib::Client client("127.0.0.1", port_);
  const auto post = client.Post("/app.js", "x", "text/plain");
  ASSERT_TRUE(post);
  EXPECT_EQ(post->status, 404);
  const auto head = client.Head("/app.js");
  ASSERT_TRUE(head);
  EXPECT_EQ(head->status, 200);
  EXPECT_TRUE(head->body.empty());
}

TEST(WebAssets, MissingRootServesNothing) {
  httplib::Server server;
  EXPECT_EQ(mountWebAssets(server, "/nonexistent/hexcover/web"), 0u);
}

TEST(WebAssets, DefaultRootIsNextToTheExecutable) {
  const fs::path executable = fs::read_symlink("/proc/self/exe");
  EXPECT_EQ(defaultWebRoot(), executable.parent_path() / "web");
}

}  // namespace
}  // namespace hexcover::server
