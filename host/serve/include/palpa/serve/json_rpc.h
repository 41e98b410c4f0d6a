// JSON-RPC 2.0 envelopes: one message read into calls (a single call or a batch), each one checked
// before any method sees it; responses, errors and notifications written.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace palpa::serve::rpc {

using Json = nlohmann::json;

/// JSON-RPC 2.0's own codes, then this server's (the -32000 range is the implementation's).
enum Code : int {
  kParseError = -32700,
  kInvalidRequest = -32600,
  kMethodNotFound = -32601,
  kInvalidParams = -32602,
  kInternalError = -32603,
  kBoardRefused = -32000,   ///< the board or the host library refused; data.status says why
  kNotController = -32001,  ///< a method that moves the board, from a client that watches
  kControlTaken = -32002,   ///< another client controls the board (take it with force)
  kTooLarge = -32003,       ///< the message exceeded the server's limit; it was dropped unread
  kNotInChannel = -32004,   ///< a view's own method (a participant's answer) from outside the view
};

struct Error {
  int code = kInternalError;
  std::string message;
  Json data;  ///< null, or {"status": "out_of_range", ...}
};

struct Call {
  Json id;                    ///< a string, an integer or null
  bool notification = false;  ///< no "id": no answer, as the specification says
  std::string method;
  Json params = Json::object();  ///< always an object here (by-name parameters)
};

/// One message as read: the calls to make, and the answers already due for entries that were not
/// calls at all (parse errors, invalid requests). `batch`: the answers go back as one array.
struct Parsed {
  std::vector<Call> calls;
  std::vector<Json> answers;
  bool batch = false;
};

/// Never throws. A batch larger than `max_batch` is one invalid-request error.
Parsed ParseMessage(std::string_view text, size_t max_batch);

Json Result(const Json& id, Json result);
Json ErrorAnswer(const Json& id, const Error& error);
Json Notification(const std::string& method, Json params);

/// A message's text as it goes out: invalid UTF-8 from anywhere replaced, never thrown on.
std::string Text(const Json& message);

}  // namespace palpa::serve::rpc
