#pragma once
/// @file
/// cobra studio's HTTP + WebSocket server (Boost.Beast; protocol: studio/PROTOCOL.md): one thread
/// of its own running an asio io_context. It serves the web front end's files, the source's model,
/// recording and inputs, and streams the newest frame to every WebSocket client at most
/// `frame_rate` times per wall-clock second. A client that reads slowly gets fewer frames: each
/// client has at most one frame waiting (the newest replaces it) and a bounded queue of event
/// messages (the oldest dropped), so nothing grows and no thread of the run ever waits on it.
/// Every request needs the token (query `token=`, header X-Cobra-Token or cookie cobra_token);
/// without it: 403 {"error":"missing or wrong token"}, for a WebSocket upgrade too. Bound beyond
/// loopback (isLoopback) or with require_tls, it serves HTTPS and WSS only, with the certificate
/// and key it is given; what a client may send and hold is bounded (ServerLimits, http.hpp).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "cobra/studio/http.hpp"
#include "cobra/studio/source.hpp"

namespace cobra::studio {

class Editor;

struct ServerOptions {
  std::string bind = "127.0.0.1";  ///< address to listen on (an IP address)
  /// PEM certificate (chain) and private key: with them the server speaks TLS only (HTTPS, WSS).
  /// Required when `bind` is beyond loopback or require_tls is set.
  std::filesystem::path tls_cert, tls_key;
  /// Treat `bind` as reachable from other hosts although it is a loopback address (one that ssh
  /// or a proxy forwards): TLS is then required as beyond loopback. The tests use it on 127.0.0.1.
  bool require_tls = false;
  ServerLimits limits;             ///< what a client may send and hold (http.hpp)
  unsigned short port = 0;         ///< 0: any free port
  std::filesystem::path web_folder;  ///< the built front end (index.html, assets/); "" = none
  std::string token;               ///< "" = a random one (randomToken)
  double frame_rate = 30.0;        ///< frames per wall-clock second at most, per client [Hz]
  std::size_t max_messages = 256;  ///< event messages waiting per client at most
  /// Kernel send buffer of a WebSocket client's socket [bytes] (0: the system's): small, so that
  /// a slow client's frames wait here, where the newest replaces them, not in the kernel.
  int send_buffer = 65536;
  /// The deployment editor's routes under /api/editor/ (editor.hpp); nullptr: they answer 404.
  /// Called on the server's thread; must outlive the server.
  Editor* editor = nullptr;
};

/// What the server did (tests, bench).
struct ServerStats {
  long clients = 0;             ///< WebSocket clients connected now
  long frames_sent = 0;         ///< frames written to clients
  long frames_coalesced = 0;    ///< frames replaced by a newer one before a slow client took them
  long messages_dropped = 0;    ///< event messages dropped from full client queues
  long forbidden = 0;           ///< requests refused for their token
  long connections = 0;         ///< TCP connections open now (HTTP and WebSocket)
  long connections_refused = 0; ///< connections closed at once: max_connections were open
  long requests_refused = 0;    ///< requests answered 400, 413 or 431 (over a bound, unparsable)
  long timed_out = 0;           ///< connections cut off: a request or TLS handshake not complete in time
  long tls_refused = 0;         ///< connections closed in their TLS handshake (e.g. plain HTTP to a TLS port)
};

class Server {
 public:
  /// Listens and starts the server's thread. @throws std::runtime_error "studio: cannot listen on
  /// ADDR:PORT: why", or naming the TLS certificate or key that is missing (and how to make a pair)
  /// or that does not load.
  Server(StudioSource& source, ServerOptions options);
  ~Server();  ///< stops the thread
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  unsigned short port() const;
  const std::string& token() const;
  /// "http://ADDR:PORT/?token=TOKEN" ("https://" with TLS).
  std::string url() const;
  ServerStats stats() const;
  bool tls() const;  ///< true when it speaks TLS only

  struct Impl;  ///< server.cpp's (its sessions name it)

 private:
  std::unique_ptr<Impl> impl_;
};

/// "http://ADDR:PORT/editor.html?token=TOKEN" ("https://" with TLS): the deployment editor's page.
std::string editorUrl(const Server& server);

/// 32 hexadecimal characters from std::random_device.
std::string randomToken();

/// The web front end's folder: $COBRA_STUDIO_WEB when set, else the first of
/// <exe dir>/../share/cobra/studio/web, <exe dir>/../../studio/web/dist (a build tree) and
/// <exe dir>/../../../studio/web/dist that holds index.html; "" when none does.
std::filesystem::path findWebFolder(const std::filesystem::path& executable);

}  // namespace cobra::studio
