// cobra studio's server under abuse (studio/src/server.cpp, http.cpp; bounds: ServerLimits): an
// oversized header, too many header fields, an oversized body, an oversized WebSocket message,
// too many connections and a request trickled byte by byte, each refused or cut off as documented;
// and a paced run with the studio attached that completes while a client does all of that, the
// server answering a good client after.

#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "cobra/run/runner.hpp"
#include "cobra/studio/bridge.hpp"
#include "cobra/studio/server.hpp"
#include "fake_source.hpp"
#include "http_client.hpp"

namespace cobra::studio {
namespace {

using namespace test_http;  // asio, beast, http, tcp
namespace websocket = beast::websocket;
using ::cobra::test_support::waitUntil;

// A raw connection: what the server sends back to `bytes` until it closes the connection.
struct Raw {
  asio::io_context io;
  tcp::socket socket{io};
  explicit Raw(unsigned short port) { socket.connect({asio::ip::make_address("127.0.0.1"), port}); }
  void send(const std::string& bytes) {
    beast::error_code ignored;  // the server may have closed already
    asio::write(socket, asio::buffer(bytes), ignored);
  }
  // Everything until the server closes (or resets) the connection.
  std::string answer() {
    std::string received;
    beast::error_code error;
    char chunk[4096];
    while (!error) received.append(chunk, socket.read_some(asio::buffer(chunk), error));
    return received;
  }
};

std::string withToken(const std::string& headers) {
  return "GET /api/model HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Cobra-Token: " + std::string(kToken) + "\r\n" + headers + "\r\n";
}

// The status line and body of an answer (the headers between them vary).
std::string statusAndBody(const std::string& answer) {
  const auto blank = answer.find("\r\n\r\n");
  return answer.substr(0, answer.find("\r\n")) + " " + (blank == std::string::npos ? "" : answer.substr(blank + 4));
}

TEST(StudioServerLimits, AnOversizedHeaderOrTooManyFieldsGets431AndTheConnectionCloses) {
  FakeSource source;
  Server server(source, options());
  Raw big(server.port());
  big.send(withToken("X-Pad: " + std::string(9000, 'x') + "\r\n"));
  EXPECT_EQ(statusAndBody(big.answer()),
            "HTTP/1.1 431 Request Header Fields Too Large {\"error\":\"request header over 8192 bytes\"}");
  std::string fields;
  for (int i = 0; i < 70; ++i) fields += "X-Field-" + std::to_string(i) + ": 1\r\n";
  Raw many(server.port());
  many.send(withToken(fields));
  EXPECT_EQ(statusAndBody(many.answer()), "HTTP/1.1 431 Request Header Fields Too Large {\"error\":\"more than 64 header fields\"}");
  // Under both bounds: answered.
  Raw fine(server.port());
  fine.send(withToken("X-Pad: " + std::string(7000, 'x') + "\r\nConnection: close\r\n"));
  EXPECT_EQ(statusAndBody(fine.answer()), "HTTP/1.1 200 OK {\"protocol\":1,\"mode\":\"live\"}");
  EXPECT_EQ(server.stats().requests_refused, 2);
}

TEST(StudioServerLimits, AnOversizedBodyGets413BeforeItIsRead) {
  FakeSource source;
  ServerOptions o = options();
  o.limits.max_body_bytes = 1000;
  Server server(source, o);
  Raw post(server.port());
  post.send("POST /api/input HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Cobra-Token: " + std::string(kToken) +
            "\r\nContent-Length: 5000000\r\n\r\n{\"name\":\"go\"");
  EXPECT_EQ(statusAndBody(post.answer()), "HTTP/1.1 413 Payload Too Large {\"error\":\"request body over 1000 bytes\"}");
  // A chunked body over the bound too.
  Raw chunked(server.port());
  chunked.send("POST /api/input HTTP/1.1\r\nHost: 127.0.0.1\r\nTransfer-Encoding: chunked\r\n\r\n800\r\n" + std::string(2048, 'x'));
  EXPECT_EQ(statusAndBody(chunked.answer()), "HTTP/1.1 413 Payload Too Large {\"error\":\"request body over 1000 bytes\"}");
  EXPECT_EQ(source.inputs.load(), 0);
  EXPECT_EQ(request(server.port(), http::verb::post, "/api/input", "{\"name\":\"go\"}", {{"X-Cobra-Token", kToken}}).status, 200);
}

TEST(StudioServerLimits, AWebSocketMessageOverItsBoundClosesTheConnectionWith1009) {
  FakeSource source;
  Server server(source, options());
  asio::io_context io;
  websocket::stream<tcp::socket> ws(io);
  ws.next_layer().connect({asio::ip::make_address("127.0.0.1"), server.port()});
  ws.handshake("127.0.0.1", std::string("/ws?token=") + kToken);
  // At the bound (4096 bytes): played.
  const std::string head = "{\"type\":\"input\",\"name\":\"go\",\"pad\":\"";
  ws.write(asio::buffer(head + std::string(4096 - head.size() - 2, 'x') + "\"}"));
  EXPECT_TRUE(waitUntil([&] { return source.inputs.load() == 1; }));
  ws.write(asio::buffer(head + std::string(4097 - head.size() - 2, 'x') + "\"}"));
  beast::error_code error;
  for (int i = 0; i < 1000 && !error; ++i) {  // frames until the close
    beast::flat_buffer buffer;
    ws.read(buffer, error);
  }
  EXPECT_EQ(error, websocket::error::closed) << error.message();
  EXPECT_EQ(ws.reason().code, websocket::close_code::too_big);
  EXPECT_EQ(source.inputs.load(), 1);
  EXPECT_TRUE(waitUntil([&] { return server.stats().clients == 0; }));
}

TEST(StudioServerLimits, AConnectionOverTheCountIsClosedAtOnceAndOneIsServedWhenASlotFrees) {
  FakeSource source;
  ServerOptions o = options();
  o.limits.max_connections = 3;
  Server server(source, o);
  std::vector<std::unique_ptr<Raw>> held;
  for (int i = 0; i < 3; ++i) held.push_back(std::make_unique<Raw>(server.port()));
  EXPECT_TRUE(waitUntil([&] { return server.stats().connections == 3; }));
  Raw over(server.port());
  over.send(withToken(""));
  EXPECT_EQ(over.answer(), "") << "closed without an answer";
  EXPECT_EQ(server.stats().connections_refused, 1);
  held.pop_back();  // closes one
  EXPECT_TRUE(waitUntil([&] { return server.stats().connections == 2; }));
  EXPECT_EQ(request(server.port(), http::verb::get, std::string("/api/model?token=") + kToken).status, 200);
}

TEST(StudioServerLimits, ARequestTrickledByteByByteIsCutOffAfterTheRequestTimeout) {
  FakeSource source;
  ServerOptions o = options();
  o.limits.request_timeout = 0.5;  // s
  Server server(source, o);
  Raw slow(server.port());
  std::atomic<bool> cut{false}, gave_up{false};
  // One header byte every 20 ms, never the end of the header: without the timeout the request
  // would go on for ever (the writer gives up after 2,000 bytes, 40 s).
  std::thread trickle([&] {
    slow.send("GET /api/model?token=" + std::string(kToken) + " HTTP/1.1\r\nX-Slow: ");
    for (int i = 0; i < 2000 && !cut.load(); ++i) {
      slow.send("x");
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    gave_up = !cut.load();
    beast::error_code ignored;
    slow.socket.shutdown(tcp::socket::shutdown_send, ignored);
  });
  const std::string answer = slow.answer();
  cut = true;
  trickle.join();
  EXPECT_FALSE(gave_up.load()) << "the server waited for the whole trickle";
  EXPECT_EQ(answer, "") << "cut off without an answer";
  // The deadline closes the socket before the read's handler counts it.
  EXPECT_TRUE(waitUntil([&] { return server.stats().timed_out == 1; }));
  // A connection that sends nothing is cut off the same way.
  Raw idle(server.port());
  EXPECT_EQ(idle.answer(), "");
  EXPECT_TRUE(waitUntil([&] { return server.stats().timed_out == 2; }));
}

// Everything above at once, from a thread, until `stop`: the held connections and trickles fill
// the connection count, the rest are refused with 413/431 or closed.
void abuse(unsigned short port, const std::atomic<bool>& stop) {
  std::vector<std::unique_ptr<Raw>> held;
  while (!stop.load()) {
    held.push_back(std::make_unique<Raw>(port));
    held.back()->send("GET /api/model HTTP/1.1\r\nX-Slow: ");  // never finished
    Raw big(port);
    big.send(withToken("X-Pad: " + std::string(20000, 'x') + "\r\n"));
    Raw body(port);
    body.send("POST /api/input HTTP/1.1\r\nContent-Length: 900000000\r\n\r\n");
    beast::error_code ignored;
    asio::io_context io;
    websocket::stream<tcp::socket> ws(io);
    ws.next_layer().connect({asio::ip::make_address("127.0.0.1"), port}, ignored);
    ws.handshake("127.0.0.1", std::string("/ws?token=") + kToken, ignored);
    ws.write(asio::buffer(std::string(100000, '{')), ignored);
    if (held.size() > 100) held.erase(held.begin());  // 2 s old or more: long cut off or refused
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

TEST(StudioServerLimits, ARunWithTheStudioCompletesWhileAClientAbusesTheServerWhichThenAnswersAGoodClient) {
  BridgeOptions recording;
  recording.record = true;
  VisualizerBridge bridge(recording);
  ServerOptions o = options();
  o.limits.max_connections = 16;
  o.limits.request_timeout = 0.5;  // s
  Server server(bridge, o);
  std::atomic<bool> stop{false};
  std::thread abuser([&] { abuse(server.port(), stop); });
  run::RunOptions options;
  options.app = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing";
  options.time_limit = 3.0;  // s
  options.pace = 1.0;        // paced to real time, as cobra run --studio
  options.observer = &bridge;
  const run::RunResult result = run::runApp(options);
  stop = true;
  abuser.join();
  EXPECT_EQ(result.outcome, run::Outcome::TimeLimit) << result.reason;
  EXPECT_NEAR(result.duration, 3.0, 1e-9);
  EXPECT_GE(bridge.stats().published, 90);
  const ServerStats stats = server.stats();
  EXPECT_GT(stats.connections_refused, 0);
  EXPECT_GT(stats.requests_refused, 0);
  EXPECT_GT(stats.timed_out, 0);
  // The abuser's connections are closed or cut off: a good client is served.
  EXPECT_TRUE(waitUntil([&] { return server.stats().connections == 0; }));
  const Reply model = request(server.port(), http::verb::get, std::string("/api/model?token=") + kToken);
  EXPECT_EQ(model.status, 200);
  EXPECT_EQ(model.body.rfind("{\"protocol\":1", 0), 0u) << model.body;
}

}  // namespace
}  // namespace cobra::studio
