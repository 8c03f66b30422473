#pragma once
// What the studio server's tests serve: a source whose frames are always new, a web folder and
// the options with a fixed token (server_test, server_tls_test, server_limits_test).

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cobra/studio/server.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::studio {
namespace test_server {

constexpr const char* kToken = "0123456789abcdef0123456789abcdef";

// A source whose frames are always new (`frame_size` bytes) and which emits one event per call.
class FakeSource final : public StudioSource {
 public:
  std::string model(int& status) override {
    status = 200;
    return "{\"protocol\":1,\"mode\":\"live\"}";
  }
  std::string recording() override { return "{\"frames\":[]}"; }
  bool latestFrame(std::uint64_t& seq, std::string& message) override {
    ++seq;
    message = "{\"type\":\"frame\",\"t\":" + std::to_string(seq) + ",\"pad\":\"" + std::string(frame_size, 'x') + "\"}";
    return true;
  }
  void takeMessages(std::vector<std::string>& messages) override {
    if (events) messages.push_back("{\"type\":\"event\",\"t\":0,\"source\":\"fake\",\"name\":\"e_tick\"}");
  }
  std::filesystem::path mesh(const std::string& name) override {
    return name == "phantom" ? ::cobra::test_support::scratchPath("cobra_studio_server_web") / "index.html"
                             : std::filesystem::path();
  }
  InputAnswer input(const std::string& name) override {
    if (name != "go") return {400, "no input '" + name + "': expected one of go"};
    ++inputs;
    return {};
  }
  std::size_t frame_size = 100;
  bool events = false;
  std::atomic<int> inputs{0};
};

inline std::filesystem::path webFolder() {
  const auto folder = ::cobra::test_support::scratchPath("cobra_studio_server_web");
  std::filesystem::create_directories(folder / "assets");
  std::ofstream(folder / "index.html") << "<html>studio</html>";
  std::ofstream(folder / "assets" / "app.js") << "console.log(1);";
  return folder;
}

inline ServerOptions options() {
  ServerOptions o;
  o.token = kToken;
  o.web_folder = webFolder();
  return o;
}

}  // namespace test_server
using test_server::FakeSource;
using test_server::kToken;
using test_server::options;
using test_server::webFolder;
}  // namespace cobra::studio
