// libFuzzer target: the studio server's HTTP side without sockets (studio/src/http.cpp): the bytes
// of one connection read as requests under small bounds, checked for the token and routed
// (answerBytes), and the same bytes as a client's WebSocket message (answerWsMessage). Checks
// beyond "no crash": every answer is an HTTP/1.x status line with a status the server gives; a
// refusal over a bound names it; without the token in the bytes nothing is answered 200 and no
// input is played; an input is played over the WebSocket exactly when json::inputRequest names
// one, and the error sent back for a refused one is one JSON object of type "error".

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <string_view>

#include "cobra/studio/http.hpp"
#include "cobra/studio/json.hpp"

namespace {

namespace studio = cobra::studio;
namespace json = cobra::studio::json;

constexpr const char* kToken = "0123456789abcdef0123456789abcdef";

[[noreturn]] void fail(const char* why, const std::string& detail) {
  std::fprintf(stderr, "fuzz: %s: %s\n", why, detail.c_str());
  std::abort();
}

// A source with fixed answers that counts the inputs played (the known one: "go").
class Source final : public studio::StudioSource {
 public:
  std::string model(int& status) override {
    status = 200;
    return "{\"protocol\":1}";
  }
  std::string recording() override { return "{\"frames\":[]}"; }
  bool latestFrame(std::uint64_t&, std::string&) override { return false; }
  void takeMessages(std::vector<std::string>&) override {}
  studio::InputAnswer input(const std::string& name) override {
    ++played;
    if (name != "go") return {400, "no input '" + name + "': expected one of go"};
    return {};
  }
  std::filesystem::path mesh(const std::string&) override { return {}; }
  int played = 0;
};

// The statuses of the answers in `wire` (each "HTTP/1.x NNN ..."), checked for their form.
std::multiset<int> statuses(const std::string& wire) {
  static const std::set<int> known = {200, 400, 403, 404, 405, 413, 431, 500};
  std::multiset<int> found;
  for (std::size_t at = wire.find("HTTP/1."); at != std::string::npos; at = wire.find("\r\n\r\nHTTP/1.", at + 1)) {
    if (at != 0) at += 4;
    if (wire.size() < at + 12 || wire[at + 8] != ' ') fail("an answer without a status line", wire.substr(at, 40));
    const int status = std::atoi(wire.substr(at + 9, 3).c_str());
    if (known.count(status) == 0) fail("a status the server does not give", wire.substr(at, 40));
    found.insert(status);
  }
  if (wire.rfind("HTTP/1.", 0) != 0 && !wire.empty()) fail("the answers do not start with a status line", wire.substr(0, 40));
  return found;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  studio::ServerLimits limits;  // small, so that the fuzzer reaches them
  limits.max_header_bytes = 512;
  limits.max_header_fields = 8;
  limits.max_body_bytes = 256;
  studio::Routes routes;
  routes.token = kToken;
  routes.editor = [](std::string_view, std::string_view route, std::string_view) {
    return std::pair<int, std::string>(route == "palette" ? 200 : 404, "{}");
  };
  Source source;
  const std::string wire = studio::answerBytes(source, routes, limits, bytes);
  const std::multiset<int> answered = statuses(wire);
  if (answered.count(413) > 0 && wire.find("{\"error\":\"request body over 256 bytes\"}") == std::string::npos)
    fail("a 413 that does not name the bound", wire);
  if (answered.count(431) > 0 && wire.find("{\"error\":\"request header over 512 bytes\"}") == std::string::npos &&
      wire.find("{\"error\":\"more than 8 header fields\"}") == std::string::npos)
    fail("a 431 that does not name the bound", wire);
  if (bytes.find(kToken) == std::string_view::npos) {
    if (answered.count(200) > 0) fail("answered 200 without the token", std::string(bytes));
    if (source.played > 0) fail("played an input without the token", std::string(bytes));
  }

  Source ws;
  const std::optional<std::string> error = studio::answerWsMessage(ws, bytes);
  const std::optional<std::string> name = json::inputRequest(bytes, true);
  if (ws.played != (name ? 1 : 0)) fail("the WebSocket message played inputs that inputRequest does not name", std::string(bytes));
  if (error.has_value() != (name.has_value() && *name != "go")) fail("an error answer for an accepted input, or none for a refused one", std::string(bytes));
  if (error) {
    const std::optional<json::Json> parsed = json::tryParse(*error);
    if (!parsed || json::stringMember(*parsed, "type") != "error") fail("an error answer that is not {\"type\":\"error\",...}", *error);
  }
  return 0;
}
