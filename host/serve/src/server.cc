// The listener, the server's thread and its tick: accepted connections become HTTP sessions.
#include "palpa/serve/server.h"

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>

#include "http_session.h"
#include "palpa/serve/api.h"
#include "palpa/serve/request_guard.h"

namespace palpa::serve {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

struct Server::Impl {
  Impl(host::Device& device, ServeOptions o, std::vector<MethodGroup> groups)
      : options(std::move(o)),
        acceptor(io),
        api(
            device, options, [this](std::function<void()> f) { asio::post(io, std::move(f)); },
            std::move(groups)) {}

  void Accept() {
    acceptor.async_accept([this](boost::beast::error_code ec, tcp::socket socket) {
      if (!ec) std::make_shared<HttpSession>(std::move(socket), api, options, *guard)->Start();
      if (acceptor.is_open()) Accept();
    });
  }

  void Tick(const std::function<bool()>& stop) {
    timer.expires_after(std::chrono::milliseconds(5));
    timer.async_wait([this, &stop](boost::beast::error_code ec) {
      if (ec) return;
      if (stop()) {
        io.stop();
        return;
      }
      api.Tick(std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
                   .count());
      Tick(stop);
    });
  }

  ServeOptions options;
  asio::io_context io;  ///< before the API: its posts land here until the end
  tcp::acceptor acceptor;
  std::unique_ptr<RequestGuard> guard;
  asio::steady_timer timer{io};
  uint16_t port = 0;
  Api api;
};

Result<std::unique_ptr<Server>> Server::Bind(host::Device& device, ServeOptions options,
                                             std::vector<MethodGroup> groups) {
  if (!options.listen.loopback && options.token.empty()) {
    auto token = NewToken();
    if (!token.ok()) return token.outcome();
    options.token = token.value;
  }
  auto impl = std::make_unique<Impl>(device, options, std::move(groups));
  boost::beast::error_code ec;
  const tcp::endpoint at(asio::ip::make_address(options.listen.address, ec), options.listen.port);
  if (!ec) impl->acceptor.open(at.protocol(), ec);
  if (!ec) impl->acceptor.set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) impl->acceptor.bind(at, ec);
  if (!ec) impl->acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) {
    return Outcome::Fail(host::Status::kUnavailable, "cannot listen on " + options.listen.address +
                                                         ":" + std::to_string(options.listen.port) +
                                                         ": " + ec.message());
  }
  impl->port = impl->acceptor.local_endpoint().port();
  if (!options.truth_address.empty()) {
    auto truth = std::make_unique<host::TruthReader>(1000);  // the newest second at 1 ms
    if (!truth->Connect(options.truth_address)) {
      return Outcome::Fail(host::Status::kUnavailable,
                           "cannot read the simulator's truth channel at " + options.truth_address);
    }
    impl->api.SetTruth(std::move(truth));
  }
  impl->guard = std::make_unique<RequestGuard>(impl->options, impl->port);
  return std::unique_ptr<Server>(new Server(std::move(impl)));
}

Server::Server(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Server::~Server() = default;

uint16_t Server::port() const { return impl_->port; }

std::string Server::Url() const {
  const std::string& a = impl_->options.listen.address;
  const std::string host = a.find(':') != std::string::npos ? "[" + a + "]" : a;
  return "http://" + host + ":" + std::to_string(impl_->port) + "/" +
         (impl_->options.token.empty() ? "" : "?token=" + impl_->options.token);
}

void Server::Run(const std::function<bool()>& stop) {
  impl_->Accept();
  impl_->Tick(stop);
  impl_->io.run();
}

}  // namespace palpa::serve
