// HTTP requests to the server: checked, then a file of the page or the WebSocket upgrade.
#include "http_session.h"

#include <sys/stat.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "ws_session.h"

namespace palpa::serve {
namespace {

const char* ContentType(const std::string& path) {
  const auto ends = [&](const char* s) {
    const std::string suffix(s);
    return path.size() >= suffix.size() &&
           path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (ends(".html")) return "text/html; charset=utf-8";
  if (ends(".js")) return "text/javascript; charset=utf-8";
  if (ends(".css")) return "text/css; charset=utf-8";
  if (ends(".svg")) return "image/svg+xml";
  if (ends(".png")) return "image/png";
  return "application/octet-stream";
}

/// A path inside the web root: letters, digits, '-', '_', '.', '/' only, no "..", no hidden file.
bool SafePath(const std::string& path) {
  if (path.empty() || path[0] != '/' || path.find("..") != std::string::npos ||
      path.find("/.") != std::string::npos || path.size() > 200)
    return false;
  for (char c : path) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.' &&
        c != '/')
      return false;
  }
  return true;
}

}  // namespace

HttpSession::HttpSession(tcp::socket socket, Api& api, const ServeOptions& options,
                         const RequestGuard& guard)
    : stream_(std::move(socket)), api_(api), options_(options), guard_(guard) {
  beast::error_code ec;
  const auto remote = stream_.socket().remote_endpoint(ec);
  peer_ = ec ? "unknown peer" : remote.address().to_string() + ":" + std::to_string(remote.port());
}

void HttpSession::Read() {
  parser_.emplace();
  parser_->header_limit(8 * 1024);
  parser_->body_limit(8 * 1024);
  stream_.expires_after(std::chrono::seconds(30));
  http::async_read(stream_, buffer_, *parser_,
                   [self = shared_from_this()](beast::error_code ec, size_t) {
                     if (ec) return;  // closed, timed out or malformed: nothing to answer
                     self->OnRequest();
                   });
}

void HttpSession::OnRequest() {
  Request request = parser_->release();
  RequestFacts facts;
  facts.host = std::string(request[http::field::host]);
  facts.has_origin = request.find(http::field::origin) != request.end();
  facts.origin = std::string(request[http::field::origin]);
  facts.target = std::string(request.target());
  facts.cookie = std::string(request[http::field::cookie]);
  facts.authorization = std::string(request[http::field::authorization]);
  const GuardVerdict verdict = guard_.Check(facts);
  if (!verdict.allowed) {
    std::fprintf(stderr, "palpa serve: refused %s %s from %s: %s\n",
                 std::string(request.method_string()).c_str(), facts.target.substr(0, 80).c_str(),
                 peer_.c_str(), verdict.reason.c_str());
    Response r =
        Plain(request, static_cast<http::status>(verdict.http_status), verdict.reason + "\n");
    r.keep_alive(false);
    return Write(std::move(r));
  }
  const std::string path = facts.target.substr(0, facts.target.find('?'));
  if (websocket::is_upgrade(request)) {
    if (path != "/websocket") {
      return Write(Plain(request, http::status::not_found, "the WebSocket is at /websocket\n"));
    }
    stream_.expires_never();
    auto ws = std::make_shared<WsSession>(stream_.release_socket(), api_, options_, peer_);
    ws->Start(std::move(request));
    return;
  }
  if (request.method() != http::verb::get && request.method() != http::verb::head) {
    return Write(Plain(request, http::status::method_not_allowed, "only GET and HEAD\n"));
  }
  Response r = File(request, path == "/" ? "/index.html" : path);
  if (verdict.set_token_cookie) {
    r.set(http::field::set_cookie,
          std::string(kTokenCookie) + "=" + options_.token + "; HttpOnly; SameSite=Strict; Path=/");
  }
  Write(std::move(r));
}

HttpSession::Response HttpSession::Plain(const Request& request, http::status status,
                                         const std::string& text) const {
  Response r{status, request.version()};
  r.set(http::field::content_type, "text/plain; charset=utf-8");
  r.body() = text;
  r.keep_alive(request.keep_alive());
  return r;
}

HttpSession::Response HttpSession::File(const Request& request, const std::string& path) const {
  if (options_.web_root.empty())
    return Plain(request, http::status::not_found,
                 "palpa serve: the API is at /websocket (no page)\n");
  if (!SafePath(path)) return Plain(request, http::status::not_found, "not found\n");
  const std::string full = options_.web_root + path;
  struct stat st {};
  std::ifstream in(full, std::ios::binary);
  if (stat(full.c_str(), &st) != 0 || !S_ISREG(st.st_mode) || !in) {
    return Plain(request, http::status::not_found, "not found\n");
  }
  std::ostringstream body;
  body << in.rdbuf();
  Response r{http::status::ok, request.version()};
  r.set(http::field::content_type, ContentType(path));
  r.set(http::field::cache_control, "no-store");
  r.set("X-Content-Type-Options", "nosniff");
  r.set("X-Frame-Options", "DENY");  // no other site frames the page (and its E-stop)
  r.set("Content-Security-Policy",
        "default-src 'self'; connect-src 'self'; img-src 'self' data:; frame-ancestors 'none'");
  r.body() = request.method() == http::verb::head ? "" : body.str();
  r.keep_alive(request.keep_alive());
  return r;
}

void HttpSession::Write(Response response) {
  response.prepare_payload();
  auto shared = std::make_shared<Response>(std::move(response));
  http::async_write(stream_, *shared,
                    [self = shared_from_this(), shared](beast::error_code ec, size_t) {
                      if (ec || !shared->keep_alive()) {
                        beast::error_code ignored;
                        self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
                        return;
                      }
                      self->Read();
                    });
}

}  // namespace palpa::serve
