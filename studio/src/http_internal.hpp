#pragma once
// The Beast side of http.hpp, shared by server.cpp (on sockets) and http.cpp (answerBytes).

#include <string>

#include <boost/beast/core/error.hpp>
#include <boost/beast/http.hpp>

#include "cobra/studio/http.hpp"

namespace cobra::studio::detail {

namespace http = boost::beast::http;
using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;
using RequestParser = http::request_parser<http::string_body>;

/// A parser for one request under `limits` (header and body bytes).
void limitParser(RequestParser& parser, const ServerLimits& limits);

/// After reading a request with `parser` (result `error`): 0 when it is to be routed; -1 when the
/// connection is to be closed without a word (it closed, timed out, or stopped mid-request); else
/// the status of the refusal (400, 413, 431) and `why` its body's error text.
int refusal(const boost::beast::error_code& error, const RequestParser& parser, const ServerLimits& limits, std::string& why);

/// The answer to a refused request (Connection: close).
Response refusalResponse(int status, const std::string& why, unsigned version);

bool authorised(const Request& request, const std::string& token);

/// True when `request` is a WebSocket upgrade of /ws with the token: the server accepts it.
bool acceptsUpgrade(const Request& request, const Routes& routes);

/// The answer to an accepted request; `forbidden` set when it was refused for its token.
Response route(StudioSource& source, const Routes& routes, const Request& request, bool& forbidden);

}  // namespace cobra::studio::detail
