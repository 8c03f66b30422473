// The studio server's HTTP side without sockets (studio/src/http.cpp): answerBytes on pipelined,
// incomplete, refused and upgraded requests, and answerWsMessage, the two entries
// fuzz/studio_http_fuzz.cpp drives with arbitrary bytes.

#include <gtest/gtest.h>

#include <string>

#include "cobra/studio/http.hpp"
#include "fake_source.hpp"

namespace cobra::studio {
namespace {

const std::string kAuth = std::string("X-Cobra-Token: ") + kToken + "\r\n";

Routes routes() {
  Routes r;
  r.token = kToken;
  return r;
}

// The status lines of `wire`, one per answer.
std::vector<std::string> statusLines(const std::string& wire) {
  std::vector<std::string> lines;
  for (std::size_t at = wire.find("HTTP/1."); at != std::string::npos; at = wire.find("HTTP/1.", at + 1))
    lines.push_back(wire.substr(at, wire.find("\r\n", at) - at));
  return lines;
}

TEST(StudioHttp, AnswersPipelinedRequestsInTurnUntilOneClosesTheConnection) {
  FakeSource source;
  const std::string wire = answerBytes(source, routes(), {},
                                       "GET /api/model HTTP/1.1\r\n" + kAuth + "\r\n" +
                                           "POST /api/input HTTP/1.1\r\n" + kAuth + "Content-Length: 13\r\n\r\n{\"name\":\"go\"}" +
                                           "GET /api/nothing HTTP/1.1\r\n" + kAuth + "Connection: close\r\n\r\n" +
                                           "GET /api/model HTTP/1.1\r\n" + kAuth + "\r\n");
  EXPECT_EQ(statusLines(wire), (std::vector<std::string>{"HTTP/1.1 200 OK", "HTTP/1.1 200 OK", "HTTP/1.1 404 Not Found"}));
  EXPECT_NE(wire.find("{\"protocol\":1,\"mode\":\"live\"}"), std::string::npos);
  EXPECT_NE(wire.find("{\"error\":\"no such resource: /api/nothing\"}"), std::string::npos);
  EXPECT_EQ(source.inputs.load(), 1);
}

TEST(StudioHttp, AnIncompleteRequestGetsNoAnswerAndARefusalEndsTheConnection) {
  FakeSource source;
  EXPECT_EQ(answerBytes(source, routes(), {}, "GET /api/model HTTP/1.1\r\n" + kAuth), "");
  EXPECT_EQ(answerBytes(source, routes(), {}, "POST /api/input HTTP/1.1\r\n" + kAuth + "Content-Length: 13\r\n\r\n{\"na"), "");
  ServerLimits small;
  small.max_body_bytes = 4;
  const std::string refused = answerBytes(source, routes(), small,
                                          "POST /api/input HTTP/1.1\r\nContent-Length: 13\r\n\r\n{\"name\":\"go\"}"
                                          "GET /api/model HTTP/1.1\r\n" + kAuth + "\r\n");
  EXPECT_EQ(statusLines(refused), std::vector<std::string>{"HTTP/1.1 413 Payload Too Large"});
  EXPECT_NE(refused.find("Connection: close\r\n"), std::string::npos);
  EXPECT_NE(refused.find("{\"error\":\"request body over 4 bytes\"}"), std::string::npos);
  const std::string bad = answerBytes(source, routes(), {}, "GET /api/model HTTP/9.9\r\n\r\n");
  EXPECT_EQ(statusLines(bad), std::vector<std::string>{"HTTP/1.1 400 Bad Request"});
  EXPECT_NE(bad.find("{\"error\":\"bad request: bad version\"}"), std::string::npos) << bad;
  EXPECT_EQ(source.inputs.load(), 0);
}

TEST(StudioHttp, AnAcceptedUpgradeEndsTheHttpAnswersAndOneWithoutTheTokenIsRefused) {
  FakeSource source;
  const std::string upgrade = "GET /ws?token=TOKEN HTTP/1.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                              "Sec-WebSocket-Version: 13\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\r\n"
                              "GET /api/model HTTP/1.1\r\n" + kAuth + "\r\n";
  std::string accepted = upgrade;
  accepted.replace(accepted.find("TOKEN"), 5, kToken);
  EXPECT_EQ(answerBytes(source, routes(), {}, accepted), "");
  // Refused, the connection stays HTTP: the next request is answered.
  EXPECT_EQ(statusLines(answerBytes(source, routes(), {}, upgrade)),
            (std::vector<std::string>{"HTTP/1.1 403 Forbidden", "HTTP/1.1 200 OK"}));
}

TEST(StudioHttp, AWebSocketInputIsPlayedAndARefusedOneAnsweredWithItsError) {
  FakeSource source;
  EXPECT_EQ(answerWsMessage(source, "{\"type\":\"input\",\"name\":\"go\"}"), std::nullopt);
  EXPECT_EQ(source.inputs.load(), 1);
  EXPECT_EQ(answerWsMessage(source, "{\"type\":\"input\",\"name\":\"stop\"}"),
            "{\"type\":\"error\",\"error\":\"no input 'stop': expected one of go\"}");
  EXPECT_EQ(answerWsMessage(source, "{\"name\":\"go\"}"), std::nullopt) << "no type: not a command";
  EXPECT_EQ(answerWsMessage(source, "{{"), std::nullopt);
  EXPECT_EQ(source.inputs.load(), 1);
}

}  // namespace
}  // namespace cobra::studio
