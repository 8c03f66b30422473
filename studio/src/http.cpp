#include "cobra/studio/http.hpp"

#include <fstream>
#include <sstream>

#include <boost/asio/buffer.hpp>
#include <boost/asio/ip/address.hpp>
#include <boost/beast/websocket/rfc6455.hpp>

#include "cobra/studio/json.hpp"
#include "http_internal.hpp"

namespace cobra::studio {
namespace detail {
namespace {

const char* kForbidden = "{\"error\":\"missing or wrong token\"}";

std::string contentType(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json" || ext == ".map") return "application/json";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".png") return "image/png";
  if (ext == ".wasm") return "application/wasm";
  if (ext == ".woff2") return "font/woff2";
  return "application/octet-stream";
}

// The value of `key` in a query string or a Cookie header ("a=1&b=2", "a=1; b=2").
std::string valueIn(std::string_view text, std::string_view key, char separator) {
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && text[i] == ' ') ++i;
    std::size_t end = text.find(separator, i);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view pair = text.substr(i, end - i);
    const auto eq = pair.find('=');
    if (eq != std::string_view::npos && pair.substr(0, eq) == key) return std::string(pair.substr(eq + 1));
    i = end + 1;
  }
  return {};
}

std::string pathOf(const Request& request) {
  const std::string target(request.target());
  return target.substr(0, target.find('?'));
}

}  // namespace

void limitParser(RequestParser& parser, const ServerLimits& limits) {
  parser.header_limit(static_cast<std::uint32_t>(std::min<std::size_t>(limits.max_header_bytes, UINT32_MAX)));
  parser.body_limit(limits.max_body_bytes);
}

int refusal(const boost::beast::error_code& error, const RequestParser& parser, const ServerLimits& limits, std::string& why) {
  if (error == http::error::header_limit) {
    why = "request header over " + std::to_string(limits.max_header_bytes) + " bytes";
    return 431;
  }
  if (error == http::error::body_limit) {
    why = "request body over " + std::to_string(limits.max_body_bytes) + " bytes";
    return 413;
  }
  // The end of the stream, a timeout, a reset: nothing to answer. A message Beast cannot parse:
  // 400 (its own words say what was wrong).
  if (error && error.category() != http::make_error_code(http::error::bad_target).category()) return -1;
  if (error == http::error::end_of_stream || error == http::error::partial_message || error == http::error::need_more) return -1;
  if (error) {
    why = "bad request: " + error.message();
    return 400;
  }
  const auto& fields = parser.get().base();
  if (static_cast<std::size_t>(std::distance(fields.begin(), fields.end())) > limits.max_header_fields) {
    why = "more than " + std::to_string(limits.max_header_fields) + " header fields";
    return 431;
  }
  return 0;
}

Response refusalResponse(int status, const std::string& why, unsigned version) {
  Response response{static_cast<http::status>(status), version == 10 ? 10u : 11u};
  response.set(http::field::content_type, "application/json");
  response.set(http::field::cache_control, "no-store");
  response.keep_alive(false);
  response.body() = json::errorBody(why);
  response.prepare_payload();
  return response;
}

bool authorised(const Request& request, const std::string& token) {
  const std::string target(request.target());
  const auto q = target.find('?');
  if (q != std::string::npos && valueIn(std::string_view(target).substr(q + 1), "token", '&') == token) return true;
  const auto header = request.find("X-Cobra-Token");
  if (header != request.end() && header->value() == token) return true;
  const auto cookie = request.find(http::field::cookie);
  return cookie != request.end() && valueIn(std::string_view(cookie->value().data(), cookie->value().size()), "cobra_token", ';') == token;
}

bool acceptsUpgrade(const Request& request, const Routes& routes) {
  return boost::beast::websocket::is_upgrade(request) && pathOf(request) == "/ws" && authorised(request, routes.token);
}

Response route(StudioSource& source, const Routes& routes, const Request& request, bool& forbidden) {
  Response response{http::status::ok, request.version()};
  response.keep_alive(request.keep_alive());
  response.set(http::field::cache_control, "no-store");
  const auto reply = [&](int status, std::string body, const std::string& type = "application/json") {
    response.result(static_cast<http::status>(status));
    response.set(http::field::content_type, type);
    response.body() = std::move(body);
    response.prepare_payload();
    return response;
  };
  forbidden = !authorised(request, routes.token);
  if (forbidden) return reply(403, kForbidden);
  const std::string path = pathOf(request);
  const bool get = request.method() == http::verb::get || request.method() == http::verb::head;
  if (path.rfind("/api/editor/", 0) == 0) {
    if (!routes.editor)
      return reply(404, "{\"error\":\"the deployment editor is not served here (cobra edit, cobra run APP --studio)\"}");
    auto [status, body] = routes.editor(std::string(request.method_string()), path.substr(12), request.body());
    return reply(status, std::move(body));
  }
  if (path == "/api/model" && get) {
    int status = 200;
    std::string body = source.model(status);
    return reply(status, std::move(body));
  }
  if (path == "/api/recording" && get) return reply(200, source.recording());
  if (path == "/api/input") {
    if (request.method() != http::verb::post) return reply(405, "{\"error\":\"POST /api/input {\\\"name\\\": \\\"INPUT\\\"}\"}");
    const std::optional<std::string> name = json::inputRequest(request.body(), false);
    if (!name) return reply(400, "{\"error\":\"expected a body {\\\"name\\\": \\\"INPUT\\\"}\"}");
    const InputAnswer answer = source.input(*name);
    if (answer.status == 200) return reply(200, "{\"ok\":true}");
    return reply(answer.status, json::errorBody(answer.error));
  }
  if (!get) return reply(405, "{\"error\":\"method not allowed\"}");
  if (path.rfind("/api/mesh/", 0) == 0) {
    const std::filesystem::path file = source.mesh(path.substr(10));
    std::ifstream in(file, std::ios::binary);
    if (file.empty() || !in) return reply(404, json::errorBody("no mesh for object '" + path.substr(10) + "'"));
    std::stringstream body;
    body << in.rdbuf();
    return reply(200, body.str(), file.extension() == ".obj" || file.extension() == ".OBJ" ? "model/obj" : "model/stl");
  }
  if (path.rfind("/api/", 0) == 0) return reply(404, json::errorBody("no such resource: " + path));
  // The web front end's files.
  const std::string relative = path == "/" ? "index.html" : path.substr(1);
  if (relative.find("..") != std::string::npos || relative.find('\\') != std::string::npos)
    return reply(400, "{\"error\":\"bad path\"}");
  if (routes.web_folder.empty() || !std::filesystem::is_regular_file(routes.web_folder / "index.html"))
    return reply(404, "{\"error\":\"the studio web front end is not built (studio/web/dist, or set COBRA_STUDIO_WEB)\"}");
  const std::filesystem::path file = routes.web_folder / relative;
  std::ifstream in(file, std::ios::binary);
  if (!std::filesystem::is_regular_file(file) || !in) return reply(404, json::errorBody("not found: " + path));
  std::stringstream body;
  body << in.rdbuf();
  if (path == "/" || path == "/editor.html")
    response.set(http::field::set_cookie, "cobra_token=" + routes.token + "; HttpOnly; SameSite=Strict; Path=/");
  return reply(200, body.str(), contentType(file));
}

}  // namespace detail

bool isLoopback(std::string_view address) {
  if (address == "localhost") return true;
  boost::system::error_code error;
  const auto ip = boost::asio::ip::make_address(std::string(address), error);
  if (error) return false;
  if (ip.is_v4()) return ip.to_v4().is_loopback();
  const auto v6 = ip.to_v6();
  return v6.is_loopback() || (v6.is_v4_mapped() && boost::asio::ip::make_address_v4(boost::asio::ip::v4_mapped, v6).is_loopback());
}

std::string answerBytes(StudioSource& source, const Routes& routes, const ServerLimits& limits, std::string_view bytes) {
  std::ostringstream out;
  while (!bytes.empty()) {
    detail::RequestParser parser;
    detail::limitParser(parser, limits);
    boost::beast::error_code error;
    // As http::read does: the parser takes what it can of the bytes, the rest waits for more.
    while (!parser.is_done() && !bytes.empty()) {
      const std::size_t used = parser.put(boost::asio::buffer(bytes.data(), bytes.size()), error);
      bytes.remove_prefix(used);
      if (error == detail::http::error::need_more) {
        if (used == 0) break;  // a part that needs more than there is: the connection waits (and times out)
        error = {};
      } else if (error) {
        break;
      }
    }
    if (!error && !parser.is_done()) break;  // incomplete: no answer
    std::string why;
    const int status = detail::refusal(error, parser, limits, why);
    if (status < 0) break;
    if (status > 0) {
      out << detail::refusalResponse(status, why, parser.get().version());
      break;
    }
    const detail::Request& request = parser.get();
    if (detail::acceptsUpgrade(request, routes)) break;
    bool forbidden = false;
    const detail::Response response = detail::route(source, routes, request, forbidden);
    out << response;
    if (response.need_eof()) break;
  }
  return out.str();
}

std::optional<std::string> answerWsMessage(StudioSource& source, std::string_view message) {
  const std::optional<std::string> name = json::inputRequest(message, true);
  if (!name) return std::nullopt;
  const InputAnswer answer = source.input(*name);
  if (answer.status == 200) return std::nullopt;
  return "{\"type\":\"error\",\"error\":" + json::quoted(answer.error) + "}";
}

}  // namespace cobra::studio
