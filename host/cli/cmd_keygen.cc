// palpa keygen: a key pair to sign firmware packages with (palpa package --sign).
#include <cstdio>

#include "cli.h"
#include "palpa/host/signing_key.h"

namespace palpa::cli {

int CmdKeygen(Context&, const std::vector<std::string>& args) {
  if (args.size() != 1 || args[0].empty() || args[0][0] == '-')
    return Usage("keygen", "needs one FILE: the private key's (FILE.pub gets the public key)");
  const auto id = host::WriteKeyPair(args[0]);
  if (!id.ok()) return Fail("keygen", id.status, id.message, kExitUsage);
  if (JsonOutput()) {
    PrintJson({{"private_key", args[0]}, {"public_key", args[0] + ".pub"}, {"key_id", id.value}});
    return kExitOk;
  }
  std::printf("key %s: private %s (mode 0600: keep it secret), public %s.pub\n", id.value.c_str(),
              args[0].c_str(), args[0].c_str());
  return kExitOk;
}

const Command kKeygenCommand{
    "keygen", "keygen FILE",
    "Writes a new Ed25519 key pair for signing firmware: FILE, the private key (created with\n"
    "mode 0600; an existing file is never overwritten), and FILE.pub, the public key a board's\n"
    "firmware is built to trust (PALPA_TRUSTED_KEYS). Prints the key id palpa flash shows.\n"
    "docs/flashing.md.",
    CmdKeygen};

}  // namespace palpa::cli
