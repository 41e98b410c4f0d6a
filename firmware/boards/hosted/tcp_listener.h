// A non-blocking TCP listening socket from "tcp:IPV4:PORT" (port 0 picks a free one), shared by
// the hosted boards' links and palpa-sim's truth channel (--truth).
#pragma once

#include <string>

namespace palpa::hosted {

/// Parses `spec` ("tcp:" already checked by the caller), binds and listens. On success returns
/// the socket and sets `address` to "tcp:HOST:PORT" with the port actually bound; on failure
/// returns -1 and sets `error`, which names `option` and `spec`.
int ListenTcp(const std::string& spec, const char* option, std::string* address,
              std::string* error);

}  // namespace palpa::hosted
