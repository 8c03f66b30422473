// libFuzzer target: the studio's JSON reading (studio/src/json.cpp on nlohmann-json), the path
// every client message, editor request and recording takes. Checks beyond "no crash": an error is
// one line "JSON: ... expected WHAT"; a document that parses writes back to text that parses to
// the same document, and its strings written by json::quoted read back; tryParse and
// inputRequest agree with parse.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "cobra/studio/json.hpp"

namespace {

namespace json = cobra::studio::json;

[[noreturn]] void fail(const char* why, const std::string& detail) {
  std::fprintf(stderr, "fuzz: %s: %s\n", why, detail.c_str());
  std::abort();
}

// Every string of `v` (keys too) read back from what json::quoted writes.
void checkStrings(const json::Json& v) {
  if (v.is_string()) {
    const std::string& s = v.get_ref<const std::string&>();
    if (json::parse(json::quoted(s)) != v) fail("a string written by quoted reads back different", s);
  } else if (v.is_object()) {
    for (const auto& [key, member] : v.items()) {
      if (json::parse(json::quoted(key)).get<std::string>() != key) fail("a key written by quoted reads back different", key);
      checkStrings(member);
    }
  } else if (v.is_array()) {
    for (const json::Json& item : v) checkStrings(item);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::optional<json::Json> parsed;
  try {
    parsed = json::parse(text);
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    if (message.rfind("JSON: ", 0) != 0 || message.find("expected ") == std::string::npos || message.find('\n') != std::string::npos)
      fail("an error that is not one line 'JSON: ... expected ...'", message);
  }
  if (json::tryParse(text).has_value() != parsed.has_value()) fail("tryParse and parse disagree", std::string(text));
  const auto name = [&](bool with_type) -> std::optional<std::string> {
    if (!parsed || size > json::kMaxMessageBytes) return std::nullopt;
    if (with_type && json::stringMember(*parsed, "type") != "input") return std::nullopt;
    return json::stringMember(*parsed, "name");
  };
  if (json::inputRequest(text, true) != name(true) || json::inputRequest(text, false) != name(false))
    fail("inputRequest disagrees with parse", std::string(text));
  if (!parsed) return 0;
  const std::string written = parsed->dump();
  if (json::parse(written) != *parsed) fail("a document written back reads different", written);
  checkStrings(*parsed);
  (void)json::describe(*parsed);
  return 0;
}
