// cobra studio's server (studio/src/server.cpp) through a small Beast client: the token on every
// request and on the WebSocket upgrade, the files of the web folder, inputs, frames and events
// streamed; a client that stops reading and one that disappears while a real run goes on.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <thread>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "cobra/run/runner.hpp"
#include "cobra/studio/bridge.hpp"
#include "cobra/studio/server.hpp"
#include "fake_source.hpp"
#include "http_client.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::studio {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

TEST(StudioServer, RefusesEveryRequestAndTheWebSocketUpgradeWithoutTheRightToken) {
  FakeSource source;
  Server server(source, options());
  for (const std::string target : {"/", "/api/model", "/api/recording", "/assets/app.js", "/api/model?token=wrong"}) {
    const Reply r = request(server.port(), http::verb::get, target);
    EXPECT_EQ(r.status, 403) << target;
    EXPECT_EQ(r.body, "{\"error\":\"missing or wrong token\"}") << target;
  }
  EXPECT_EQ(request(server.port(), http::verb::post, "/api/input", "{\"name\":\"go\"}").status, 403);
  EXPECT_EQ(request(server.port(), http::verb::get, "/api/model", {}, {{"X-Cobra-Token", "nope"}}).status, 403);
  EXPECT_EQ(source.inputs.load(), 0);

  asio::io_context io;
  websocket::stream<tcp::socket> ws(io);
  ws.next_layer().connect({asio::ip::make_address("127.0.0.1"), server.port()});
  websocket::response_type response;
  beast::error_code refused;
  ws.handshake(response, "127.0.0.1", "/ws", refused);
  EXPECT_EQ(refused, websocket::error::upgrade_declined) << refused.message();
  // The same upgrade request by hand, to see the answer (Beast 1.74 keeps it from the caller).
  const Reply upgrade = request(server.port(), http::verb::get, "/ws?token=wrong",  {},
                                {{"Upgrade", "websocket"}, {"Connection", "Upgrade"}, {"Sec-WebSocket-Version", "13"},
                                 {"Sec-WebSocket-Key", "dGhlIHNhbXBsZSBub25jZQ=="}});
  EXPECT_EQ(upgrade.status, 403);
  EXPECT_EQ(upgrade.body, "{\"error\":\"missing or wrong token\"}");
  EXPECT_EQ(server.stats().forbidden, 9);
}

TEST(StudioServer, ServesTheWebFolderAndTheApiWithTheTokenInTheQueryAHeaderOrItsCookie) {
  FakeSource source;
  Server server(source, options());
  const Reply page = request(server.port(), http::verb::get, std::string("/?token=") + kToken);
  EXPECT_EQ(page.status, 200);
  EXPECT_EQ(page.body, "<html>studio</html>");
  EXPECT_EQ(page.type, "text/html; charset=utf-8");
  EXPECT_EQ(page.cookie, std::string("cobra_token=") + kToken + "; HttpOnly; SameSite=Strict; Path=/");
  const Reply script = request(server.port(), http::verb::get, "/assets/app.js", {}, {{"Cookie", std::string("a=1; cobra_token=") + kToken}});
  EXPECT_EQ(script.status, 200);
  EXPECT_EQ(script.type, "text/javascript; charset=utf-8");
  const Reply model = request(server.port(), http::verb::get, "/api/model", {}, {{"X-Cobra-Token", kToken}});
  EXPECT_EQ(model.status, 200);
  EXPECT_EQ(model.body, "{\"protocol\":1,\"mode\":\"live\"}");
  EXPECT_EQ(request(server.port(), http::verb::get, std::string("/../secret?token=") + kToken).status, 400);
  EXPECT_EQ(request(server.port(), http::verb::get, std::string("/assets/none.js?token=") + kToken).status, 404);
  const Reply mesh = request(server.port(), http::verb::get, std::string("/api/mesh/phantom?token=") + kToken);
  EXPECT_EQ(mesh.status, 200);
  EXPECT_EQ(mesh.body, "<html>studio</html>");  // the file the source names, as it is
  EXPECT_EQ(mesh.type, "model/stl");
  const Reply none = request(server.port(), http::verb::get, std::string("/api/mesh/table?token=") + kToken);
  EXPECT_EQ(none.status, 404);
  EXPECT_EQ(none.body, "{\"error\":\"no mesh for object 'table'\"}");
  EXPECT_EQ(server.url(), "http://127.0.0.1:" + std::to_string(server.port()) + "/?token=" + kToken);
}

TEST(StudioServer, PlaysInputsAndNamesTheKnownOnesForAnUnknownOne) {
  FakeSource source;
  Server server(source, options());
  const std::vector<std::pair<std::string, std::string>> token = {{"X-Cobra-Token", kToken}};
  const Reply ok = request(server.port(), http::verb::post, "/api/input", "{\"name\":\"go\"}", token);
  EXPECT_EQ(ok.status, 200);
  EXPECT_EQ(ok.body, "{\"ok\":true}");
  const Reply unknown = request(server.port(), http::verb::post, "/api/input", "{\"name\":\"stop\"}", token);
  EXPECT_EQ(unknown.status, 400);
  EXPECT_EQ(unknown.body, "{\"error\":\"no input 'stop': expected one of go\"}");
  EXPECT_EQ(request(server.port(), http::verb::post, "/api/input", "name=go", token).status, 400);
  EXPECT_EQ(source.inputs.load(), 1);
}

TEST(StudioServer, StreamsFramesAndEventsAndTakesInputsOverTheWebSocket) {
  FakeSource source;
  source.events = true;
  Server server(source, options());
  asio::io_context io;
  websocket::stream<tcp::socket> ws(io);
  ws.next_layer().connect({asio::ip::make_address("127.0.0.1"), server.port()});
  ws.handshake("127.0.0.1", std::string("/ws?token=") + kToken);
  ws.write(asio::buffer(std::string("{\"type\":\"input\",\"name\":\"go\"}")));
  int frames = 0, events = 0;
  const auto start = std::chrono::steady_clock::now();
  while (frames < 5) {
    beast::flat_buffer buffer;
    ws.read(buffer);
    const std::string text = beast::buffers_to_string(buffer.data());
    frames += text.rfind("{\"type\":\"frame\"", 0) == 0;
    events += text.rfind("{\"type\":\"event\"", 0) == 0;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(events, 4);
  EXPECT_LE(frames, 30.0 * seconds + 2.0) << "at most 30 frames per wall-clock second";
  EXPECT_EQ(source.inputs.load(), 1);
  ws.close(websocket::close_code::normal);
}

// A WebSocket client whose kernel receive buffer is tiny and that never reads.
struct SlowClient {
  asio::io_context io;
  websocket::stream<tcp::socket> ws{io};
  explicit SlowClient(unsigned short port) {
    ws.next_layer().open(tcp::v4());
    ws.next_layer().set_option(asio::socket_base::receive_buffer_size(2048));
    ws.next_layer().connect({asio::ip::make_address("127.0.0.1"), port});
    ws.handshake("127.0.0.1", std::string("/ws?token=") + kToken);
  }
};

TEST(StudioServer, AClientThatStopsReadingGetsTheNewestFrameOnlyAndTheOthersAreServed) {
  FakeSource source;
  source.frame_size = 32768;  // B: a few frames fill the kernel buffers
  source.events = true;
  ServerOptions o = options();
  o.send_buffer = 8192;
  o.max_messages = 4;
  Server server(source, o);
  SlowClient slow(server.port());
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const ServerStats stats = server.stats();
  EXPECT_GT(stats.frames_coalesced, 0);
  EXPECT_LT(stats.frames_sent, 20) << "the slow client's socket is full after a few frames";
  EXPECT_GT(stats.messages_dropped, 0) << "its event queue is bounded";
  // Another client is served meanwhile.
  asio::io_context io;
  websocket::stream<tcp::socket> ws(io);
  ws.next_layer().connect({asio::ip::make_address("127.0.0.1"), server.port()});
  ws.handshake("127.0.0.1", std::string("/ws?token=") + kToken);
  beast::flat_buffer buffer;
  ws.read(buffer);
  EXPECT_EQ(request(server.port(), http::verb::get, std::string("/api/model?token=") + kToken).status, 200);
}

TEST(StudioServer, ARunGoesOnWithAClientThatStopsReadingAndOneThatDisappears) {
  BridgeOptions recording;
  recording.record = true;
  VisualizerBridge bridge(recording);
  ServerOptions o = options();
  o.send_buffer = 8192;
  Server server(bridge, o);
  SlowClient slow(server.port());
  std::atomic<bool> vanished{false};
  std::thread gone([&] {
    asio::io_context io;
    websocket::stream<tcp::socket> ws(io);
    ws.next_layer().connect({asio::ip::make_address("127.0.0.1"), server.port()});
    ws.handshake("127.0.0.1", std::string("/ws?token=") + kToken);
    beast::flat_buffer buffer;
    ws.read(buffer);  // one frame, then the socket is closed without a word
    ws.next_layer().close();
    vanished = true;
  });
  run::RunOptions options;
  options.app = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing";
  options.time_limit = 3.0;  // s
  options.pace = 1.0;        // paced to real time, as cobra run --studio: 3 s of wall clock
  options.observer = &bridge;
  const run::RunResult result = run::runApp(options);
  gone.join();
  EXPECT_EQ(result.outcome, run::Outcome::TimeLimit) << result.reason;
  EXPECT_NEAR(result.duration, 3.0, 1e-9);
  EXPECT_TRUE(vanished.load());
  EXPECT_GT(server.stats().frames_coalesced, 0) << "the slow client's frames were replaced, not queued";
  EXPECT_GE(bridge.stats().published, 90);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(server.stats().clients, 1) << "the vanished client is gone, the slow one still connected";
  // A client that comes after the run gets its end and its last frame.
  asio::io_context io;
  websocket::stream<tcp::socket> late(io);
  late.next_layer().connect({asio::ip::make_address("127.0.0.1"), server.port()});
  late.handshake("127.0.0.1", std::string("/ws?token=") + kToken);
  beast::flat_buffer end, frame;
  late.read(end);
  late.read(frame);
  EXPECT_EQ(beast::buffers_to_string(end.data()), "{\"type\":\"end\",\"t\":3,\"outcome\":\"time limit\",\"message\":\"" +
                                                   result.reason + "\",\"status\":1,\"line\":\"" + run::endLine(result) +
                                                   "\",\"states\":{\"needle\":\"" + result.final_states[0].second +
                                                   "\",\"us\":\"" + result.final_states[1].second + "\"}}");
  EXPECT_EQ(beast::buffers_to_string(frame.data()).rfind("{\"type\":\"frame\",\"t\":3,\"robots\":{\"isur\":", 0), 0u);
}

}  // namespace
}  // namespace cobra::studio
