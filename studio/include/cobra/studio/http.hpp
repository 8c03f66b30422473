#pragma once
/// @file
/// The studio server's HTTP side without sockets (studio/PROTOCOL.md "Security"): the bounds a
/// client's requests and messages must keep, the loopback rule that decides whether TLS is
/// required, and what the server answers to the bytes of a connection (parsing under the bounds,
/// the token check, the routing) and to a WebSocket message. server.cpp serves these on sockets;
/// fuzz/studio_http_fuzz.cpp drives them with arbitrary bytes.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "cobra/studio/source.hpp"

namespace cobra::studio {

/// What a client may send and hold. A request over a bound is answered (413 or 431, body
/// {"error":"..."} naming the bound) and its connection closed; a connection over the count, a
/// request or TLS handshake not complete in time, and a WebSocket message over its bound are
/// closed without an answer (the WebSocket one with close code 1009, "too big").
struct ServerLimits {
  std::size_t max_header_bytes = 8192;      ///< request line and header fields [bytes]; over: 431
  std::size_t max_header_fields = 64;       ///< header fields of a request; over: 431 (browsers send ~20)
  std::size_t max_body_bytes = 1 << 20;     ///< request body [bytes]; over: 413 (editor saves: a few KiB)
  std::size_t max_ws_message_bytes = 4096;  ///< a client's WebSocket message [bytes] (an input command: ~50)
  std::size_t max_connections = 64;         ///< open TCP connections, HTTP and WebSocket together
  /// Time a client has to send a whole request, from its first byte or the connection's start,
  /// and to complete a TLS handshake [s]: a request trickled byte by byte (slowloris) is cut off.
  double request_timeout = 10.0;
};

/// What the routes serve besides the source (ServerOptions' token, web_folder and editor).
struct Routes {
  std::string token;                 ///< every request needs it (query token=, X-Cobra-Token, cookie cobra_token)
  std::filesystem::path web_folder;  ///< the built front end; "" = none (404 saying so)
  /// The deployment editor's routes (Editor::handle: method, route after /api/editor/, body) ->
  /// status and JSON body; empty: /api/editor/ answers 404.
  std::function<std::pair<int, std::string>(std::string_view, std::string_view, std::string_view)> editor;
};

/// True for an address only this host reaches: 127.0.0.0/8, ::1, ::ffff:127.x.y.z and
/// "localhost". Anything else (0.0.0.0, ::, a host's address, a name) is beyond loopback: the
/// server then serves HTTPS and WSS only and refuses to start without a certificate and key.
bool isLoopback(std::string_view address);

/// The answers the server writes to `bytes` received on one plain connection, in order, as the
/// text on the wire: requests are read under `limits`, checked for the token and routed, until
/// one that closes the connection (a refusal, Connection: close, an accepted WebSocket upgrade,
/// whose frames are not HTTP) or the bytes end (an incomplete request gets no answer).
std::string answerBytes(StudioSource& source, const Routes& routes, const ServerLimits& limits, std::string_view bytes);

/// What the server does with a client's WebSocket message: {"type":"input","name":N} plays input
/// N on the source; the answer is the error message sent back when the source refuses it
/// ({"type":"error","error":"..."}), nothing otherwise (also for any other or malformed text).
std::optional<std::string> answerWsMessage(StudioSource& source, std::string_view message);

}  // namespace cobra::studio
