#include "cobra/studio/server.hpp"

#include <atomic>
#include <cstdlib>
#include <deque>
#include <optional>
#include <random>
#include <stdexcept>
#include <thread>
#include <type_traits>
#include <vector>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>

#include "cobra/studio/editor.hpp"
#include "cobra/studio/json.hpp"
#include "http_internal.hpp"

namespace cobra::studio {
namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace ssl = asio::ssl;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using TlsStream = beast::ssl_stream<beast::tcp_stream>;

namespace {

// A WebSocket client as the tick sees it (plain or TLS).
class WsClient {
 public:
  virtual ~WsClient() = default;
  virtual void offerFrame(const std::shared_ptr<const std::string>& frame) = 0;
  virtual void offerMessage(const std::shared_ptr<const std::string>& message) = 0;
  virtual bool open() const = 0;
};

// One open connection counted against max_connections while its session (HTTP, then WebSocket)
// holds it.
struct ConnectionSlot {
  explicit ConnectionSlot(std::atomic<long>& count) : count_(count) { count_.fetch_add(1); }
  ~ConnectionSlot() { count_.fetch_sub(1); }
  ConnectionSlot(const ConnectionSlot&) = delete;
  ConnectionSlot& operator=(const ConnectionSlot&) = delete;

 private:
  std::atomic<long>& count_;
};

// Closes a connection after its last answer: a TCP half-close (the client reads to the end), or
// TLS's close_notify first.
template <class Stream, class Keep>
void finish(Stream& stream, Keep keep) {
  if constexpr (std::is_same_v<Stream, TlsStream>) {
    beast::get_lowest_layer(stream).expires_after(std::chrono::seconds(5));
    stream.async_shutdown([keep](beast::error_code) {});
  } else {
    beast::error_code ignored;
    stream.socket().shutdown(tcp::socket::shutdown_send, ignored);
  }
}

}  // namespace

// Owned by the Server, which joins the io thread before destroying it: the sessions keep a plain
// pointer to it (the io_context's destructor then releases the sessions its handlers hold, so the
// members they touch then, the counters and the TLS context, are declared before it).
struct Server::Impl {
  Impl(StudioSource& s, ServerOptions o) : source(s), options(std::move(o)), acceptor(io), timer(io) {}

  StudioSource& source;
  ServerOptions options;
  Routes routes;
  std::atomic<long> clients{0}, frames_sent{0}, frames_coalesced{0}, messages_dropped{0}, forbidden{0};
  std::atomic<long> connections{0}, connections_refused{0}, requests_refused{0}, timed_out{0}, tls_refused{0};
  std::optional<ssl::context> tls;  // set: TLS only
  asio::io_context io;
  tcp::acceptor acceptor;
  asio::steady_timer timer;
  std::thread thread;
  unsigned short port = 0;
  std::vector<std::weak_ptr<WsClient>> sessions;  // the io thread's only
  std::uint64_t frame_seq = 0;
  asio::steady_timer::time_point next_tick{};
  std::shared_ptr<const std::string> last_frame, end_message;
  std::string frame_text;
  std::vector<std::string> messages;

  std::chrono::steady_clock::duration requestTimeout() const {
    return std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(options.limits.request_timeout));
  }
  void accept();
  void tick();
};

namespace {

// One WebSocket client: at most one frame waiting (the newest) and a bounded message queue.
template <class Stream>
class WsSession final : public WsClient, public std::enable_shared_from_this<WsSession<Stream>> {
 public:
  WsSession(Stream&& stream, Server::Impl* server, std::shared_ptr<ConnectionSlot> slot)
      : ws_(std::move(stream)), server_(server), slot_(std::move(slot)) {}

  void start(detail::Request request) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(server_->options.limits.max_ws_message_bytes);  // over it: closed with 1009
    if (server_->options.send_buffer > 0) {
      beast::error_code ignored;
      beast::get_lowest_layer(ws_).socket().set_option(asio::socket_base::send_buffer_size(server_->options.send_buffer), ignored);
    }
    ws_.async_accept(request, [self = this->shared_from_this()](beast::error_code error) {
      if (error) return;
      self->open_ = true;
      self->server_->clients.fetch_add(1);
      // A client that comes late gets the newest frame and, after the run, its end.
      if (self->server_->end_message) self->offerMessage(self->server_->end_message);
      if (self->server_->last_frame) self->offerFrame(self->server_->last_frame);
      self->read();
      self->flush();
    });
  }

  void offerFrame(const std::shared_ptr<const std::string>& frame) override {
    if (frame_) server_->frames_coalesced.fetch_add(1);
    frame_ = frame;
    flush();
  }
  void offerMessage(const std::shared_ptr<const std::string>& message) override {
    if (messages_.size() >= server_->options.max_messages) {
      messages_.pop_front();
      server_->messages_dropped.fetch_add(1);
    }
    messages_.push_back(message);
    flush();
  }
  bool open() const override { return open_ && !closed_; }

 private:
  void read() {
    ws_.async_read(in_, [self = this->shared_from_this()](beast::error_code error, std::size_t) {
      // Over max_ws_message_bytes Beast has sent the close frame 1009 (too big) and the read
      // ends with message_too_big: the connection goes.
      if (error) return self->close();
      const std::string text = beast::buffers_to_string(self->in_.data());
      self->in_.consume(self->in_.size());
      if (std::optional<std::string> answer = answerWsMessage(self->server_->source, text))
        self->offerMessage(std::make_shared<const std::string>(std::move(*answer)));
      self->read();
    });
  }

  void flush() {
    if (!open() || writing_) return;
    if (!messages_.empty()) {
      out_ = messages_.front();
      messages_.pop_front();
    } else if (frame_) {
      out_ = std::move(frame_);
      frame_.reset();
      server_->frames_sent.fetch_add(1);
    } else {
      return;
    }
    writing_ = true;
    ws_.text(true);
    ws_.async_write(asio::buffer(*out_), [self = this->shared_from_this()](beast::error_code error, std::size_t) {
      self->writing_ = false;
      self->out_.reset();
      if (error) return self->close();
      self->flush();
    });
  }

  void close() {
    if (closed_) return;
    closed_ = true;
    if (open_) server_->clients.fetch_sub(1);
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().close(ignored);
  }

  websocket::stream<Stream> ws_;
  Server::Impl* server_;
  std::shared_ptr<ConnectionSlot> slot_;
  beast::flat_buffer in_;
  std::shared_ptr<const std::string> frame_, out_;
  std::deque<std::shared_ptr<const std::string>> messages_;
  bool open_ = false, closed_ = false, writing_ = false;
};

// One HTTP connection (plain or TLS): requests read under the limits and answered in turn, or
// upgraded to a WebSocket at /ws.
template <class Stream>
class HttpSession : public std::enable_shared_from_this<HttpSession<Stream>> {
 public:
  HttpSession(Stream&& stream, Server::Impl* server, std::shared_ptr<ConnectionSlot> slot)
      : stream_(std::move(stream)), server_(server), slot_(std::move(slot)) {}

  // TLS: the handshake first, within the request timeout; one that fails (a client speaking plain
  // HTTP, a wrong version, no shared cipher) closes the connection without a byte of HTTP.
  void start() {
    if constexpr (std::is_same_v<Stream, TlsStream>) {
      beast::get_lowest_layer(stream_).expires_after(server_->requestTimeout());
      stream_.async_handshake(ssl::stream_base::server, [self = this->shared_from_this()](beast::error_code error) {
        if (error) {
          (error == beast::error::timeout ? self->server_->timed_out : self->server_->tls_refused).fetch_add(1);
          beast::error_code ignored;
          beast::get_lowest_layer(self->stream_).socket().close(ignored);
          return;
        }
        self->read();
      });
    } else {
      read();
    }
  }

 private:
  void read() {
    parser_.emplace();
    detail::limitParser(*parser_, server_->options.limits);
    // One deadline for the whole request: bytes trickling in do not extend it (slowloris).
    beast::get_lowest_layer(stream_).expires_after(server_->requestTimeout());
    http::async_read(stream_, buffer_, *parser_, [self = this->shared_from_this()](beast::error_code error, std::size_t) {
      if (error == beast::error::timeout) self->server_->timed_out.fetch_add(1);
      std::string why;
      const int status = detail::refusal(error, *self->parser_, self->server_->options.limits, why);
      if (status < 0) return;  // the session ends: its socket closes
      if (status > 0) {
        self->server_->requests_refused.fetch_add(1);
        return self->write(detail::refusalResponse(status, why, self->parser_->get().version()));
      }
      self->handle(self->parser_->release());
    });
  }

  void handle(detail::Request request) {
    if (detail::acceptsUpgrade(request, server_->routes)) {
      beast::get_lowest_layer(stream_).expires_never();  // the WebSocket stream keeps its own timeouts
      auto ws = std::make_shared<WsSession<Stream>>(std::move(stream_), server_, std::move(slot_));
      server_->sessions.push_back(ws);
      ws->start(std::move(request));
      return;
    }
    bool forbidden = false;
    detail::Response response = detail::route(server_->source, server_->routes, request, forbidden);
    if (forbidden) server_->forbidden.fetch_add(1);
    write(std::move(response));
  }

  void write(detail::Response answer) {
    auto response = std::make_shared<detail::Response>(std::move(answer));
    http::async_write(stream_, *response, [self = this->shared_from_this(), response](beast::error_code error, std::size_t) {
      if (error) return;
      if (response->need_eof()) return finish(self->stream_, self);
      self->read();
    });
  }

  Stream stream_;
  Server::Impl* server_;
  std::shared_ptr<ConnectionSlot> slot_;
  beast::flat_buffer buffer_;
  std::optional<detail::RequestParser> parser_;
};

}  // namespace

// Over max_connections a new connection is closed at once, before a byte is read: a client cannot
// hold more of the server than that, and those it holds time out unless they finish requests.
void Server::Impl::accept() {
  acceptor.async_accept([this](beast::error_code error, tcp::socket socket) {
    if (error) return;  // closed: the server stops
    if (connections.load() >= static_cast<long>(options.limits.max_connections)) {
      connections_refused.fetch_add(1);
      beast::error_code ignored;
      socket.close(ignored);
    } else {
      auto slot = std::make_shared<ConnectionSlot>(connections);
      if (tls)
        std::make_shared<HttpSession<TlsStream>>(TlsStream(std::move(socket), *tls), this, std::move(slot))->start();
      else
        std::make_shared<HttpSession<beast::tcp_stream>>(beast::tcp_stream(std::move(socket)), this, std::move(slot))->start();
    }
    accept();
  });
}

void Server::Impl::tick() {
  // On a fixed schedule (each tick one period after the one before, not after it ran), so that a
  // busy thread does not stretch the period; one that fell more than a period behind starts again.
  const auto period = std::chrono::duration_cast<asio::steady_timer::duration>(std::chrono::duration<double>(1.0 / options.frame_rate));
  const auto now = asio::steady_timer::clock_type::now();
  next_tick = next_tick + period < now ? now + period : next_tick + period;
  timer.expires_at(next_tick);
  timer.async_wait([this](beast::error_code error) {
    Impl* self = this;
    if (error) return;
    std::erase_if(self->sessions, [](const std::weak_ptr<WsClient>& s) { return s.expired(); });
    self->messages.clear();
    self->source.takeMessages(self->messages);
    std::shared_ptr<const std::string> frame;
    if (self->source.latestFrame(self->frame_seq, self->frame_text)) self->last_frame = frame = std::make_shared<const std::string>(self->frame_text);
    std::vector<std::shared_ptr<const std::string>> shared;
    for (const std::string& m : self->messages) {
      shared.push_back(std::make_shared<const std::string>(m));
      if (m.rfind("{\"type\":\"end\"", 0) == 0) self->end_message = shared.back();
    }
    for (const auto& weak : self->sessions) {
      const auto session = weak.lock();
      if (!session || !session->open()) continue;
      for (const auto& m : shared) session->offerMessage(m);
      if (frame) session->offerFrame(frame);
    }
    self->tick();
  });
}

namespace {

const char* kMakeAPair =
    "; make a self-signed pair with: openssl req -x509 -newkey rsa:2048 -nodes -days 365 -subj /CN=HOST "
    "-addext subjectAltName=DNS:HOST -keyout studio.key -out studio.crt (HOST: the name clients use)";

// OpenSSL's reason ("no start line") rather than asio's "asio.ssl error".
std::string why(const beast::error_code& error) {
  if (error.category() == asio::error::get_ssl_category())
    if (const char* reason = ERR_reason_error_string(static_cast<unsigned long>(error.value()))) return reason;
  return error.message();
}

// The TLS context of a server beyond loopback: TLS 1.2 or newer, the certificate chain and key in
// PEM; each refusal names the file and the option.
void loadTls(ssl::context& context, const ServerOptions& options, const std::string& where) {
  const bool cert = !options.tls_cert.empty(), key = !options.tls_key.empty();
  if (!cert || !key)
    throw std::runtime_error("studio: listening on " + where + (options.require_tls ? " (TLS required)" : " (beyond loopback)") +
                             " serves HTTPS only and needs a TLS certificate and key: missing " +
                             (!cert && !key ? "--tls-cert FILE and --tls-key FILE" : !cert ? "--tls-cert FILE" : "--tls-key FILE") +
                             " (cobra run: --studio-tls-cert, --studio-tls-key; ServerOptions tls_cert, tls_key)" + kMakeAPair);
  context.set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 | ssl::context::no_sslv3 |
                      ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1 | ssl::context::single_dh_use);
  for (const auto& [file, option] : {std::pair{options.tls_cert, "--tls-cert"}, std::pair{options.tls_key, "--tls-key"}})
    if (!std::filesystem::is_regular_file(file))
      throw std::runtime_error("studio: the TLS " + std::string(option == std::string("--tls-cert") ? "certificate" : "key") +
                               " '" + file.string() + "' (" + option + ") is not a file" + kMakeAPair);
  beast::error_code error;
  context.use_certificate_chain_file(options.tls_cert.string(), error);
  if (error)
    throw std::runtime_error("studio: the TLS certificate '" + options.tls_cert.string() + "' (--tls-cert) does not load: " +
                             why(error) + "; expected a PEM certificate" + kMakeAPair);
  context.use_private_key_file(options.tls_key.string(), ssl::context::pem, error);
  const bool mismatch = error && error.category() == asio::error::get_ssl_category() &&
                        ERR_GET_REASON(static_cast<unsigned long>(error.value())) == X509_R_KEY_VALUES_MISMATCH;
  if (error && !mismatch)
    throw std::runtime_error("studio: the TLS key '" + options.tls_key.string() + "' (--tls-key) does not load: " +
                             why(error) + "; expected a PEM private key without a passphrase" + kMakeAPair);
  if (mismatch || SSL_CTX_check_private_key(context.native_handle()) != 1)
    throw std::runtime_error("studio: the TLS key '" + options.tls_key.string() + "' does not match the certificate '" +
                             options.tls_cert.string() + "'" + kMakeAPair);
}

}  // namespace

Server::Server(StudioSource& source, ServerOptions options) : impl_(std::make_unique<Impl>(source, std::move(options))) {
  Impl& m = *impl_;
  if (m.options.token.empty()) m.options.token = randomToken();
  m.routes.token = m.options.token;
  m.routes.web_folder = m.options.web_folder;
  if (Editor* editor = m.options.editor)
    m.routes.editor = [editor](std::string_view method, std::string_view route, std::string_view body) {
      EditorAnswer answer = editor->handle(method, route, body);
      return std::pair<int, std::string>(answer.status, std::move(answer.body));
    };
  beast::error_code error;
  const auto address = asio::ip::make_address(m.options.bind, error);
  const std::string where = m.options.bind + ":" + std::to_string(m.options.port);
  if (error) throw std::runtime_error("studio: cannot listen on " + where + ": not an IP address");
  // Beyond loopback the token would cross the network in clear text: TLS, or no server.
  if (m.options.require_tls || !isLoopback(m.options.bind) || !m.options.tls_cert.empty() || !m.options.tls_key.empty())
    loadTls(m.tls.emplace(ssl::context::tls_server), m.options, where);
  const tcp::endpoint endpoint(address, m.options.port);
  m.acceptor.open(endpoint.protocol(), error);
  if (!error) m.acceptor.set_option(asio::socket_base::reuse_address(true), error);
  if (!error) m.acceptor.bind(endpoint, error);
  if (!error) m.acceptor.listen(asio::socket_base::max_listen_connections, error);
  if (error) throw std::runtime_error("studio: cannot listen on " + where + ": " + error.message());
  m.port = m.acceptor.local_endpoint().port();
  m.accept();
  m.tick();
  m.thread = std::thread([&m] { m.io.run(); });
}

Server::~Server() {
  impl_->io.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

unsigned short Server::port() const { return impl_->port; }
const std::string& Server::token() const { return impl_->options.token; }
std::string Server::url() const {
  return (impl_->tls ? "https://" : "http://") + impl_->options.bind + ":" + std::to_string(impl_->port) + "/?token=" + impl_->options.token;
}
std::string editorUrl(const Server& server) {
  std::string url = server.url();
  return url.replace(url.find("/?token="), 8, "/editor.html?token=");
}
ServerStats Server::stats() const {
  const Impl& m = *impl_;
  return {m.clients.load(), m.frames_sent.load(), m.frames_coalesced.load(), m.messages_dropped.load(), m.forbidden.load(),
          m.connections.load(), m.connections_refused.load(), m.requests_refused.load(), m.timed_out.load(), m.tls_refused.load()};
}
bool Server::tls() const { return impl_->tls.has_value(); }

std::string randomToken() {
  std::random_device random;
  static const char* hex = "0123456789abcdef";
  std::string token;
  for (int i = 0; i < 32; ++i) token += hex[random() % 16];
  return token;
}

std::filesystem::path findWebFolder(const std::filesystem::path& executable) {
  if (const char* env = std::getenv("COBRA_STUDIO_WEB"); env != nullptr && *env != '\0') return env;
  std::error_code error;
  const std::filesystem::path exe = std::filesystem::weakly_canonical(executable, error);
  const std::filesystem::path dir = exe.parent_path();
  for (const std::filesystem::path& candidate :
       {dir / "../share/cobra/studio/web", dir / "../../studio/web/dist", dir / "../../../studio/web/dist"})
    if (std::filesystem::is_regular_file(candidate / "index.html")) return std::filesystem::weakly_canonical(candidate, error);
  return {};
}

}  // namespace cobra::studio
