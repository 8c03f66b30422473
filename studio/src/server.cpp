#include "cobra/studio/server.hpp"

#include <atomic>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "cobra/studio/editor.hpp"
#include "cobra/studio/json.hpp"

namespace cobra::studio {
namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

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

}  // namespace

class WsSession;

// Owned by the Server, which joins the io thread before destroying it: the sessions keep a plain
// pointer to it (the io_context's destructor then releases the sessions its handlers hold).
struct Server::Impl {
  Impl(StudioSource& s, ServerOptions o) : source(s), options(std::move(o)), acceptor(io), timer(io) {}

  StudioSource& source;
  ServerOptions options;
  asio::io_context io;
  tcp::acceptor acceptor;
  asio::steady_timer timer;
  std::thread thread;
  unsigned short port = 0;
  std::vector<std::weak_ptr<WsSession>> sessions;  // the io thread's only
  std::uint64_t frame_seq = 0;
  asio::steady_timer::time_point next_tick{};
  std::shared_ptr<const std::string> last_frame, end_message;
  std::string frame_text;
  std::vector<std::string> messages;
  std::atomic<long> clients{0}, frames_sent{0}, frames_coalesced{0}, messages_dropped{0}, forbidden{0};

  void accept();
  void tick();
  bool authorised(const http::request<http::string_body>& request) const;
  http::response<http::string_body> respond(const http::request<http::string_body>& request);
};

// One WebSocket client: at most one frame waiting (the newest) and a bounded message queue.
class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(tcp::socket socket, Server::Impl* server)
      : ws_(std::move(socket)), server_(server) {}

  void start(http::request<http::string_body> request) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(json::kMaxMessageBytes);  // a client's messages are a few bytes; HTTP bodies: Beast's 1 MiB
    if (server_->options.send_buffer > 0) {
      beast::error_code ignored;
      beast::get_lowest_layer(ws_).socket().set_option(asio::socket_base::send_buffer_size(server_->options.send_buffer), ignored);
    }
    ws_.async_accept(request, [self = shared_from_this()](beast::error_code error) {
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

  void offerFrame(const std::shared_ptr<const std::string>& frame) {
    if (frame_) server_->frames_coalesced.fetch_add(1);
    frame_ = frame;
    flush();
  }
  void offerMessage(const std::shared_ptr<const std::string>& message) {
    if (messages_.size() >= server_->options.max_messages) {
      messages_.pop_front();
      server_->messages_dropped.fetch_add(1);
    }
    messages_.push_back(message);
    flush();
  }
  bool open() const { return open_ && !closed_; }

 private:
  void read() {
    ws_.async_read(in_, [self = shared_from_this()](beast::error_code error, std::size_t) {
      if (error) return self->close();
      const std::string text = beast::buffers_to_string(self->in_.data());
      self->in_.consume(self->in_.size());
      if (const std::optional<std::string> name = json::inputRequest(text, true)) {
        const InputAnswer answer = self->server_->source.input(*name);
        if (answer.status != 200)
          self->offerMessage(std::make_shared<const std::string>("{\"type\":\"error\",\"error\":" + json::quoted(answer.error) + "}"));
      }
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
    ws_.async_write(asio::buffer(*out_), [self = shared_from_this()](beast::error_code error, std::size_t) {
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

  websocket::stream<beast::tcp_stream> ws_;
  Server::Impl* server_;
  beast::flat_buffer in_;
  std::shared_ptr<const std::string> frame_, out_;
  std::deque<std::shared_ptr<const std::string>> messages_;
  bool open_ = false, closed_ = false, writing_ = false;
};

// One HTTP connection: requests answered in turn, or upgraded to a WebSocket at /ws.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, Server::Impl* server) : stream_(std::move(socket)), server_(server) {}

  void read() {
    request_ = {};
    stream_.expires_after(std::chrono::seconds(60));
    http::async_read(stream_, buffer_, request_, [self = shared_from_this()](beast::error_code error, std::size_t) {
      if (error) return;
      self->handle();
    });
  }

 private:
  void handle() {
    const std::string target(request_.target());
    const std::string path = target.substr(0, target.find('?'));
    if (websocket::is_upgrade(request_) && path == "/ws" && server_->authorised(request_)) {
      stream_.expires_never();
      auto ws = std::make_shared<WsSession>(stream_.release_socket(), server_);
      server_->sessions.push_back(ws);
      ws->start(std::move(request_));
      return;
    }
    auto response = std::make_shared<http::response<http::string_body>>(server_->respond(request_));
    http::async_write(stream_, *response, [self = shared_from_this(), response](beast::error_code error, std::size_t) {
      if (error || response->need_eof()) {
        beast::error_code ignored;
        self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
        return;
      }
      self->read();
    });
  }

  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  http::request<http::string_body> request_;
  Server::Impl* server_;
};

bool Server::Impl::authorised(const http::request<http::string_body>& request) const {
  const std::string target(request.target());
  const auto q = target.find('?');
  if (q != std::string::npos && valueIn(std::string_view(target).substr(q + 1), "token", '&') == options.token) return true;
  const auto header = request.find("X-Cobra-Token");
  if (header != request.end() && header->value() == options.token) return true;
  const auto cookie = request.find(http::field::cookie);
  return cookie != request.end() && valueIn(std::string_view(cookie->value().data(), cookie->value().size()), "cobra_token", ';') == options.token;
}

http::response<http::string_body> Server::Impl::respond(const http::request<http::string_body>& request) {
  http::response<http::string_body> response{http::status::ok, request.version()};
  response.keep_alive(request.keep_alive());
  response.set(http::field::cache_control, "no-store");
  const auto reply = [&](int status, std::string body, const std::string& type = "application/json") {
    response.result(static_cast<http::status>(status));
    response.set(http::field::content_type, type);
    response.body() = std::move(body);
    response.prepare_payload();
    return response;
  };
  if (!authorised(request)) {
    forbidden.fetch_add(1);
    return reply(403, kForbidden);
  }
  const std::string target(request.target());
  const std::string path = target.substr(0, target.find('?'));
  const bool get = request.method() == http::verb::get || request.method() == http::verb::head;
  if (path.rfind("/api/editor/", 0) == 0) {
    if (options.editor == nullptr)
      return reply(404, "{\"error\":\"the deployment editor is not served here (cobra edit, cobra run APP --studio)\"}");
    const EditorAnswer answer = options.editor->handle(std::string(request.method_string()), path.substr(12), request.body());
    return reply(answer.status, answer.body);
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
  if (options.web_folder.empty() || !std::filesystem::is_regular_file(options.web_folder / "index.html"))
    return reply(404, "{\"error\":\"the studio web front end is not built (studio/web/dist, or set COBRA_STUDIO_WEB)\"}");
  const std::filesystem::path file = options.web_folder / relative;
  std::ifstream in(file, std::ios::binary);
  if (!std::filesystem::is_regular_file(file) || !in) return reply(404, json::errorBody("not found: " + path));
  std::stringstream body;
  body << in.rdbuf();
  if (path == "/" || path == "/editor.html")
    response.set(http::field::set_cookie, "cobra_token=" + options.token + "; HttpOnly; SameSite=Strict; Path=/");
  return reply(200, body.str(), contentType(file));
}

void Server::Impl::accept() {
  acceptor.async_accept([this](beast::error_code error, tcp::socket socket) {
    if (error) return;  // closed: the server stops
    std::make_shared<HttpSession>(std::move(socket), this)->read();
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
    std::erase_if(self->sessions, [](const std::weak_ptr<WsSession>& s) { return s.expired(); });
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

Server::Server(StudioSource& source, ServerOptions options) : impl_(std::make_unique<Impl>(source, std::move(options))) {
  Impl& m = *impl_;
  if (m.options.token.empty()) m.options.token = randomToken();
  beast::error_code error;
  const auto address = asio::ip::make_address(m.options.bind, error);
  const std::string where = m.options.bind + ":" + std::to_string(m.options.port);
  if (error) throw std::runtime_error("studio: cannot listen on " + where + ": not an IP address");
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
  return "http://" + impl_->options.bind + ":" + std::to_string(impl_->port) + "/?token=" + impl_->options.token;
}
std::string editorUrl(const Server& server) {
  std::string url = server.url();
  return url.replace(url.find("/?token="), 8, "/editor.html?token=");
}
ServerStats Server::stats() const {
  const Impl& m = *impl_;
  return {m.clients.load(), m.frames_sent.load(), m.frames_coalesced.load(), m.messages_dropped.load(), m.forbidden.load()};
}

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
