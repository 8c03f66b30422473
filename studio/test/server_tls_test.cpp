// cobra studio's server beyond loopback (studio/src/server.cpp, http.cpp): the loopback rule, the
// refusal to start without a certificate and key, HTTPS and WSS with the token (and without it
// 403), plain HTTP to the TLS port closed unanswered, and the host's own non-loopback address.
// The certificates: test_pki.hpp (a test CA and a server certificate for localhost).

#include <gtest/gtest.h>

#include <ifaddrs.h>
#include <netinet/in.h>

#include <fstream>
#include <string>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>

#include "cobra/studio/server.hpp"
#include "fake_source.hpp"
#include "http_client.hpp"
#include "test_pki.hpp"

namespace cobra::studio {
namespace {

using namespace test_http;  // asio, beast, http, tcp
namespace ssl = asio::ssl;
namespace websocket = beast::websocket;

// The server's options for TLS on 127.0.0.1 (require_tls: loopback treated as beyond it).
ServerOptions tlsOptions() {
  const auto pki = test_pki::makeTestPki();
  ServerOptions o = options();
  o.require_tls = true;
  o.tls_cert = pki / "server.crt";
  o.tls_key = pki / "server.key";
  return o;
}

// A client that trusts the test CA only and checks the server's name is localhost.
ssl::context clientContext() {
  ssl::context context(ssl::context::tls_client);
  context.load_verify_file((test_pki::makeTestPki() / "ca.crt").string());
  context.set_verify_mode(ssl::verify_peer);
  context.set_verify_callback(ssl::host_name_verification("localhost"));
  return context;
}

Reply tlsRequest(const std::string& address, unsigned short port, const std::string& target,
                 const std::vector<std::pair<std::string, std::string>>& headers = {}) {
  asio::io_context io;
  ssl::context context = clientContext();
  beast::ssl_stream<tcp::socket> stream(io, context);
  stream.next_layer().connect({asio::ip::make_address(address), port});
  SSL_set_tlsext_host_name(stream.native_handle(), "localhost");
  stream.handshake(ssl::stream_base::client);
  return test_http::exchange(stream, http::verb::get, target, {}, headers);
}

std::string startError(ServerOptions o) {
  FakeSource source;
  try {
    Server server(source, o);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "started";
}

const std::string kHowToMake =
    "; make a self-signed pair with: openssl req -x509 -newkey rsa:2048 -nodes -days 365 -subj /CN=HOST "
    "-addext subjectAltName=DNS:HOST -keyout studio.key -out studio.crt (HOST: the name clients use)";

TEST(StudioServerTls, TheLoopbackRuleNamesWhatOnlyThisHostReaches) {
  for (const char* address : {"127.0.0.1", "127.0.0.2", "127.255.255.254", "::1", "::ffff:127.0.0.1", "localhost"})
    EXPECT_TRUE(isLoopback(address)) << address;
  for (const char* address : {"0.0.0.0", "::", "192.0.2.2", "10.1.2.3", "::ffff:10.0.0.1", "fe80::1", "example.org", ""})
    EXPECT_FALSE(isLoopback(address)) << address;
}

TEST(StudioServerTls, RefusesToStartBeyondLoopbackWithoutACertificateAndKeyNamingWhatIsMissing) {
  ServerOptions o = options();
  o.bind = "0.0.0.0";
  EXPECT_EQ(startError(o), "studio: listening on 0.0.0.0:0 (beyond loopback) serves HTTPS only and needs a TLS certificate "
                           "and key: missing --tls-cert FILE and --tls-key FILE (cobra run: --studio-tls-cert, --studio-tls-key; ServerOptions tls_cert, tls_key)" + kHowToMake);
  const auto pki = test_pki::makeTestPki();
  o.tls_cert = pki / "server.crt";
  EXPECT_EQ(startError(o), "studio: listening on 0.0.0.0:0 (beyond loopback) serves HTTPS only and needs a TLS certificate "
                           "and key: missing --tls-key FILE (cobra run: --studio-tls-cert, --studio-tls-key; ServerOptions tls_cert, tls_key)" + kHowToMake);
  o = options();
  o.require_tls = true;
  o.tls_key = pki / "server.key";
  EXPECT_EQ(startError(o), "studio: listening on 127.0.0.1:0 (TLS required) serves HTTPS only and needs a TLS certificate "
                           "and key: missing --tls-cert FILE (cobra run: --studio-tls-cert, --studio-tls-key; ServerOptions tls_cert, tls_key)" + kHowToMake);
  // Files that are not what they should be.
  const auto junk = pki / "junk.pem";
  std::ofstream(junk) << "not a certificate\n";
  o.tls_cert = junk;
  EXPECT_EQ(startError(o), "studio: the TLS certificate '" + junk.string() + "' (--tls-cert) does not load: no start line; "
                           "expected a PEM certificate" + kHowToMake);
  o.tls_cert = pki / "none.crt";
  EXPECT_EQ(startError(o), "studio: the TLS certificate '" + (pki / "none.crt").string() + "' (--tls-cert) is not a file" + kHowToMake);
  o.tls_cert = pki / "server.crt";
  o.tls_key = pki / "ca.key";
  EXPECT_EQ(startError(o), "studio: the TLS key '" + (pki / "ca.key").string() + "' does not match the certificate '" +
                               (pki / "server.crt").string() + "'" + kHowToMake);
  // Loopback: plain HTTP as ever, no certificate needed.
  FakeSource source;
  Server plain(source, options());
  EXPECT_FALSE(plain.tls());
  EXPECT_EQ(request(plain.port(), http::verb::get, std::string("/api/model?token=") + kToken).status, 200);
}

TEST(StudioServerTls, ServesHttpsAndWssWithTheTokenAndRefusesThemWithoutIt) {
  FakeSource source;
  Server server(source, tlsOptions());
  EXPECT_TRUE(server.tls());
  EXPECT_EQ(server.url(), "https://127.0.0.1:" + std::to_string(server.port()) + "/?token=" + kToken);
  EXPECT_EQ(editorUrl(server), "https://127.0.0.1:" + std::to_string(server.port()) + "/editor.html?token=" + kToken);
  const Reply model = tlsRequest("127.0.0.1", server.port(), std::string("/api/model?token=") + kToken);
  EXPECT_EQ(model.status, 200);
  EXPECT_EQ(model.body, "{\"protocol\":1,\"mode\":\"live\"}");
  const Reply page = tlsRequest("127.0.0.1", server.port(), "/", {{"Cookie", std::string("cobra_token=") + kToken}});
  EXPECT_EQ(page.body, "<html>studio</html>");
  const Reply refused = tlsRequest("127.0.0.1", server.port(), "/api/model?token=wrong");
  EXPECT_EQ(refused.status, 403);
  EXPECT_EQ(refused.body, "{\"error\":\"missing or wrong token\"}");

  // WSS: frames with the token, the upgrade declined without it.
  asio::io_context io;
  ssl::context context = clientContext();
  const auto connect = [&](websocket::stream<beast::ssl_stream<tcp::socket>>& ws) {
    beast::get_lowest_layer(ws).connect({asio::ip::make_address("127.0.0.1"), server.port()});
    ws.next_layer().handshake(ssl::stream_base::client);
  };
  websocket::stream<beast::ssl_stream<tcp::socket>> ws(io, context);
  connect(ws);
  ws.handshake("localhost", std::string("/ws?token=") + kToken);
  ws.write(asio::buffer(std::string("{\"type\":\"input\",\"name\":\"go\"}")));
  beast::flat_buffer frame;
  ws.read(frame);
  EXPECT_EQ(beast::buffers_to_string(frame.data()).rfind("{\"type\":\"frame\"", 0), 0u);
  EXPECT_TRUE(::cobra::test_support::waitUntil([&] { return source.inputs.load() == 1; }));
  websocket::stream<beast::ssl_stream<tcp::socket>> intruder(io, context);
  connect(intruder);
  beast::error_code declined;
  intruder.handshake("localhost", "/ws?token=wrong", declined);
  EXPECT_EQ(declined, websocket::error::upgrade_declined) << declined.message();
  EXPECT_EQ(server.stats().forbidden, 2);
}

TEST(StudioServerTls, PlainHttpToTheTlsPortIsClosedWithoutAnAnswer) {
  FakeSource source;
  Server server(source, tlsOptions());
  asio::io_context io;
  tcp::socket socket(io);
  socket.connect({asio::ip::make_address("127.0.0.1"), server.port()});
  asio::write(socket, asio::buffer(std::string("GET /api/model?token=") + kToken + " HTTP/1.1\r\nHost: localhost\r\n\r\n"));
  std::string received;
  beast::error_code error;
  char chunk[512];
  while (!error) {
    const std::size_t n = socket.read_some(asio::buffer(chunk), error);
    received.append(chunk, n);
  }
  EXPECT_TRUE(error == asio::error::eof || error == asio::error::connection_reset) << error.message();
  EXPECT_EQ(received.find("HTTP/"), std::string::npos) << "answered in plain HTTP: " << received;
  EXPECT_EQ(received.find("protocol"), std::string::npos) << "the model leaked: " << received;
  EXPECT_EQ(server.stats().tls_refused, 1);
  // The port still serves TLS.
  EXPECT_EQ(tlsRequest("127.0.0.1", server.port(), std::string("/api/model?token=") + kToken).status, 200);
}

// The first IPv4 address of this host that is not loopback ("" when it has none).
std::string hostAddress() {
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) return {};
  std::string found;
  for (const ifaddrs* a = list; a != nullptr && found.empty(); a = a->ifa_next) {
    if (a->ifa_addr == nullptr || a->ifa_addr->sa_family != AF_INET) continue;
    const auto* in = reinterpret_cast<const sockaddr_in*>(a->ifa_addr);
    const asio::ip::address_v4 v4(ntohl(in->sin_addr.s_addr));
    if (!v4.is_loopback()) found = v4.to_string();
  }
  freeifaddrs(list);
  return found;
}

TEST(StudioServerTls, OnTheHostsOwnAddressItNeedsTheCertificateAndServesTlsOnly) {
  const std::string address = hostAddress();
  if (address.empty()) GTEST_SKIP() << "this host has no IPv4 address but loopback";
  ServerOptions o = options();
  o.bind = address;
  EXPECT_EQ(startError(o).rfind("studio: listening on " + address + ":0 (beyond loopback) serves HTTPS only and needs a TLS "
                                "certificate and key: missing --tls-cert FILE and --tls-key FILE (cobra run: ", 0), 0u);
  const auto pki = test_pki::makeTestPki();
  o.tls_cert = pki / "server.crt";
  o.tls_key = pki / "server.key";
  FakeSource source;
  Server server(source, o);
  EXPECT_TRUE(server.tls());
  EXPECT_EQ(server.url(), "https://" + address + ":" + std::to_string(server.port()) + "/?token=" + kToken);
  EXPECT_EQ(tlsRequest(address, server.port(), std::string("/api/model?token=") + kToken).status, 200);
  EXPECT_EQ(tlsRequest(address, server.port(), "/api/model").status, 403);
}

}  // namespace
}  // namespace cobra::studio
