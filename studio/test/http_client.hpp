#pragma once
// A small blocking HTTP client for the studio server's tests (Boost.Beast).

#include <string>
#include <utility>
#include <vector>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

namespace cobra::studio {
namespace test_http {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

struct Reply {
  int status = 0;
  std::string body, cookie, type;
};

// One request and its answer on a connected `stream` (a socket, a TLS stream).
template <class Stream>
Reply exchange(Stream& stream, http::verb verb, const std::string& target, const std::string& body = {},
               const std::vector<std::pair<std::string, std::string>>& headers = {}) {
  http::request<http::string_body> req{verb, target, 11};
  req.set(http::field::host, "127.0.0.1");
  for (const auto& [name, value] : headers) req.set(name, value);
  req.body() = body;
  req.prepare_payload();
  http::write(stream, req);
  beast::flat_buffer buffer;
  http::response<http::string_body> res;
  http::read(stream, buffer, res);
  return {static_cast<int>(res.result_int()), res.body(), std::string(res[http::field::set_cookie]),
          std::string(res[http::field::content_type])};
}

inline Reply request(unsigned short port, http::verb verb, const std::string& target, const std::string& body = {},
              const std::vector<std::pair<std::string, std::string>>& headers = {}) {
  asio::io_context io;
  tcp::socket socket(io);
  socket.connect({asio::ip::make_address("127.0.0.1"), port});
  return exchange(socket, verb, target, body, headers);
}

}  // namespace test_http
using test_http::Reply;
using test_http::request;
}  // namespace cobra::studio
