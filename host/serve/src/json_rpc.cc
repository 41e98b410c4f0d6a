// JSON-RPC 2.0 envelopes, checked field by field.
#include "palpa/serve/json_rpc.h"

namespace palpa::serve::rpc {
namespace {

Json Invalid(const Json& id, const std::string& why) {
  return ErrorAnswer(id, Error{kInvalidRequest, "invalid request: " + why, nullptr});
}

/// One entry of a message: a call, or the answer that says why it is not one (null: nothing to
/// answer, an invalid notification being impossible to tell from an invalid request).
void ReadEntry(const Json& entry, Parsed& out) {
  if (!entry.is_object()) {
    out.answers.push_back(
        Invalid(nullptr, "expected an object, got " + std::string(entry.type_name())));
    return;
  }
  Json id = nullptr;
  const auto id_at = entry.find("id");
  if (id_at != entry.end()) {
    if (!id_at->is_string() && !id_at->is_number_integer() && !id_at->is_null()) {
      out.answers.push_back(Invalid(nullptr, "'id' must be a string, an integer or null"));
      return;
    }
    id = *id_at;
  }
  const auto version = entry.find("jsonrpc");
  if (version == entry.end() || *version != "2.0") {
    out.answers.push_back(Invalid(id, "'jsonrpc' must be \"2.0\""));
    return;
  }
  const auto method = entry.find("method");
  if (method == entry.end() || !method->is_string()) {
    out.answers.push_back(Invalid(id, "'method' must be a string"));
    return;
  }
  for (const auto& [key, value] : entry.items()) {
    (void)value;
    if (key != "jsonrpc" && key != "method" && key != "params" && key != "id") {
      out.answers.push_back(Invalid(id, "unknown member '" + key + "'"));
      return;
    }
  }
  Call call;
  call.id = id;
  call.notification = id_at == entry.end();
  call.method = method->get<std::string>();
  const auto params = entry.find("params");
  if (params != entry.end()) {
    if (!params->is_object()) {
      out.answers.push_back(ErrorAnswer(
          id, Error{kInvalidParams, "invalid params: 'params' must be an object (named parameters)",
                    nullptr}));
      return;
    }
    call.params = *params;
  }
  out.calls.push_back(std::move(call));
}

}  // namespace

Parsed ParseMessage(std::string_view text, size_t max_batch) {
  Parsed out;
  Json message = Json::parse(text.begin(), text.end(), nullptr, false);
  if (message.is_discarded()) {
    out.answers.push_back(
        ErrorAnswer(nullptr, Error{kParseError, "parse error: the message is not JSON", nullptr}));
    return out;
  }
  if (!message.is_array()) {
    ReadEntry(message, out);
    return out;
  }
  if (message.empty()) {
    out.answers.push_back(Invalid(nullptr, "an empty batch"));
    return out;
  }
  if (message.size() > max_batch) {
    out.answers.push_back(Invalid(nullptr, "a batch of " + std::to_string(message.size()) +
                                               " calls (at most " + std::to_string(max_batch) +
                                               ")"));
    return out;
  }
  out.batch = true;
  for (const Json& entry : message) ReadEntry(entry, out);
  return out;
}

Json Result(const Json& id, Json result) {
  return Json{{"jsonrpc", "2.0"}, {"id", id}, {"result", std::move(result)}};
}

Json ErrorAnswer(const Json& id, const Error& error) {
  Json e = {{"code", error.code}, {"message", error.message}};
  if (!error.data.is_null()) e["data"] = error.data;
  return Json{{"jsonrpc", "2.0"}, {"id", id}, {"error", std::move(e)}};
}

Json Notification(const std::string& method, Json params) {
  return Json{{"jsonrpc", "2.0"}, {"method", method}, {"params", std::move(params)}};
}

std::string Text(const Json& message) {
  return message.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace palpa::serve::rpc
