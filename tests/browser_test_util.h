// Browser tests (web/*.html in headless Chromium): a local HTTP server on a
// test's directory (ES modules and fetch need http:, not file:), Chromium
// with --dump-dom, and the pages' results (<pre id="..."> elements, float32
// arrays in base64).
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "tests/cli_test_util.h"

namespace clothfit {
namespace testing_util {

inline const std::string kWebDir = std::string(CLOTHFIT_SOURCE_DIR) + "/web";
inline constexpr char kChromium[] = "/usr/bin/chromium";

// Serves `root` (python3 -m http.server on a free port of 127.0.0.1) until
// destroyed.
class LocalServer {
 public:
  explicit LocalServer(const std::filesystem::path& root) : root_(root) {
    const std::string log = (root / "_server.txt").string();
    std::system(("cd " + Quote(root.string()) +
                 " && (python3 -u -m http.server 0 --bind 127.0.0.1 >" +
                 Quote(log) + " 2>&1 & echo $! >_server.pid)")
                    .c_str());
    for (int k = 0; k < 100 && port_ == 0; ++k) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      const std::string text = ReadText(log);
      const size_t at = text.find(" port ");
      if (at != std::string::npos) port_ = std::atoi(text.c_str() + at + 6);
    }
  }
  ~LocalServer() {
    const std::string pid = ReadText(root_ / "_server.pid");
    if (!pid.empty()) std::system(("kill " + pid).c_str());
  }
  LocalServer(const LocalServer&) = delete;
  LocalServer& operator=(const LocalServer&) = delete;

  int port() const { return port_; }
  std::string Url(const std::string& page) const {
    return "http://127.0.0.1:" + std::to_string(port_) + "/" + page;
  }

 private:
  std::filesystem::path root_;
  int port_ = 0;
};

// Copies web/`page` into `dir` and links web/node_modules there, so that
// LocalServer(dir) serves both.
inline void ServeWebPage(const std::filesystem::path& dir,
                         const std::string& page) {
  std::filesystem::copy_file(kWebDir + "/" + page, dir / page);
  if (!std::filesystem::exists(dir / "node_modules")) {
    std::filesystem::create_directory_symlink(kWebDir + "/node_modules",
                                              dir / "node_modules");
  }
}

// The DOM of `url` after its scripts ran (headless Chromium, SwiftShader's
// WebGL 2); "" with a test failure when Chromium fails.
inline std::string DumpDom(const std::string& url,
                           const std::filesystem::path& dir) {
  const std::string dom = (dir / "_dom.html").string();
  const std::string command =
      std::string(kChromium) +
      " --headless=new --no-sandbox --disable-dev-shm-usage "
      "--use-angle=swiftshader --enable-unsafe-swiftshader "
      "--virtual-time-budget=120000 --dump-dom " +
      Quote(url) + " >" + Quote(dom) + " 2>" + Quote(dom + ".err");
  if (std::system(command.c_str()) != 0) {
    ADD_FAILURE() << "chromium failed: " << ReadText(dom + ".err");
    return "";
  }
  return ReadText(dom);
}

// The text of <pre id="`id`"> in `dom` ("" when absent).
inline std::string PreText(const std::string& dom, const std::string& id) {
  const std::string open = "<pre id=\"" + id + "\">";
  const size_t at = dom.find(open);
  if (at == std::string::npos) return "";
  const size_t start = at + open.size();
  return dom.substr(start, dom.find("</pre>", start) - start);
}

inline std::vector<uint8_t> DecodeBase64(const std::string& text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<uint8_t> out;
  int bits = 0, buffer = 0;
  for (char c : text) {
    const int v = value(c);
    if (v < 0) continue;  // '=' padding
    buffer = ((buffer << 6) | v) & 0xffffff;
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<uint8_t>((buffer >> bits) & 0xff));
    }
  }
  return out;
}

// The floats of a page's "OK count base64" result; empty with a test
// failure for "ERROR ..." or a malformed one.
inline std::vector<float> FloatsOf(const std::string& result) {
  if (result.rfind("OK ", 0) != 0) {
    ADD_FAILURE() << "page: " << result.substr(0, 400);
    return {};
  }
  const std::vector<uint8_t> bytes =
      DecodeBase64(result.substr(result.find(' ', 3) + 1));
  std::vector<float> out(bytes.size() / sizeof(float));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(float));
  return out;
}

// Whether the browser tests can run: web/node_modules (scripts/setup.sh)
// is a failure when missing; a machine without Chromium skips (the caller
// GTEST_SKIPs on false).
inline bool BrowserAvailable() {
  EXPECT_TRUE(std::filesystem::exists(kWebDir + "/node_modules/three"))
      << "web/node_modules is missing: run scripts/setup.sh (npm ci in web/)";
  return std::filesystem::exists(kChromium);
}

}  // namespace testing_util
}  // namespace clothfit
