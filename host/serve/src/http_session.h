// One HTTP connection: every request checked by the guard (Host, Origin, token) before anything
// else; the page's files served from the web root; an upgrade on /websocket handed to a WebSocket
// session.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include "palpa/serve/api.h"
#include "palpa/serve/request_guard.h"

namespace palpa::serve {

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(boost::asio::ip::tcp::socket socket, Api& api, const ServeOptions& options,
              const RequestGuard& guard);
  void Start() { Read(); }

 private:
  using Request = boost::beast::http::request<boost::beast::http::string_body>;
  using Response = boost::beast::http::response<boost::beast::http::string_body>;

  void Read();
  void OnRequest();
  Response File(const Request& request, const std::string& path) const;
  Response Plain(const Request& request, boost::beast::http::status status,
                 const std::string& text) const;
  void Write(Response response);

  boost::beast::tcp_stream stream_;
  Api& api_;
  const ServeOptions& options_;
  const RequestGuard& guard_;
  boost::beast::flat_buffer buffer_;
  std::optional<boost::beast::http::request_parser<boost::beast::http::string_body>> parser_;
  std::string peer_;
};

}  // namespace palpa::serve
