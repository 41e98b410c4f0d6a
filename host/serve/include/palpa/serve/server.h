// `palpa serve`: one process holding the board's session, serving the page and the JSON-RPC 2.0
// API over a WebSocket (docs/serve.md) on one thread, the device called from the board worker's.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "palpa/host/device.h"
#include "palpa/serve/board_methods.h"
#include "palpa/serve/serve_options.h"

namespace palpa::serve {

class Server {
 public:
  /// Binds the listener (a token is made for a non-loopback one). `device` outlives the server.
  /// `groups`: methods beyond the board's own (a scene's), served the same way.
  static Result<std::unique_ptr<Server>> Bind(host::Device& device, ServeOptions options,
                                              std::vector<MethodGroup> groups = {});
  ~Server();

  uint16_t port() const;
  /// Where a person opens the page: http://ADDRESS:PORT/, with ?token=... when one is needed.
  std::string Url() const;
  /// Serves until `stop` returns true (asked every few milliseconds). Destroying the server then
  /// drops every client; the caller closes the device's session (every output safe, no fault).
  void Run(const std::function<bool()>& stop);

 private:
  struct Impl;
  explicit Server(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace palpa::serve
