// Key files: parsed, written (the private one created exclusively with mode 0600), and key ids.
#include "palpa/host/signing_key.h"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <sstream>

#include "palpa/host/file_write.h"
#include "palpa/protocol/sha256.h"

namespace palpa::host {
namespace {

std::string Hex(const uint8_t* bytes, size_t size) {
  static const char kDigits[] = "0123456789abcdef";
  std::string out;
  for (size_t i = 0; i < size; ++i) {
    out += kDigits[bytes[i] >> 4];
    out += kDigits[bytes[i] & 15];
  }
  return out;
}

/// The 32 bytes of a key file, or why not ("PATH: ...").
Result<std::array<uint8_t, 32>> ReadKeyBytes(const std::string& path, const char* what) {
  const auto text = ReadFileWhole(path, kKeyFileLimits);
  if (!text.ok()) return text.outcome();
  std::istringstream lines(text.value);
  std::string line, hex;
  int line_number = 0;
  while (std::getline(lines, line)) {
    ++line_number;
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const size_t last = line.find_last_not_of(" \t\r");
    if (!hex.empty()) {
      return Result<std::array<uint8_t, 32>>(
          Status::kInvalidArgument,
          path + ": line " + std::to_string(line_number) + ": a second key line; a " + what +
              " file holds one line of 64 hexadecimal digits (and '#' comments)");
    }
    hex = line.substr(first, last - first + 1);
  }
  std::array<uint8_t, 32> key{};
  size_t decoded = 0;
  if (hex.size() != 64 ||
      sodium_hex2bin(key.data(), key.size(), hex.c_str(), hex.size(), nullptr, &decoded, nullptr) !=
          0 ||
      decoded != 32) {
    return Result<std::array<uint8_t, 32>>(
        Status::kInvalidArgument, path + ": not a " + what +
                                      " file: expected one line of 64 hexadecimal digits (" +
                                      std::to_string(hex.size()) + " characters found)");
  }
  return key;
}

}  // namespace

std::string KeyId(const uint8_t* public_key) {
  const protocol::Sha256Digest d = protocol::Sha256Of(public_key, 32);
  return Hex(d.data(), 8);
}

Result<Ed25519Seed> ReadSigningKey(const std::string& path) {
  return ReadKeyBytes(path, "private key");
}

Result<Ed25519Key> ReadPublicKey(const std::string& path) {
  auto key = ReadKeyBytes(path, "public key");
  if (!key.ok()) return key.outcome();
  return key.value;
}

Result<std::string> WriteKeyPair(const std::string& private_path) {
  const std::string public_path = private_path + ".pub";
  struct stat st;
  if (lstat(public_path.c_str(), &st) == 0)
    return Result<std::string>(Status::kInvalidArgument,
                               public_path + ": exists; not overwritten (choose another name)");
  const Ed25519Signer key = Ed25519Signer::Generate();
  const std::string id = KeyId(key.PublicKey());
  // The private key: created here and now (O_EXCL: an existing file or a planted link is
  // refused, never overwritten), readable by its owner alone.
  const int fd =
      open(private_path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd < 0) {
    return Result<std::string>(errno == EEXIST ? Status::kInvalidArgument : Status::kIoError,
                               private_path + ": " +
                                   (errno == EEXIST ? std::string("exists; not overwritten")
                                                    : std::string(std::strerror(errno))));
  }
  const std::string secret = "# palpa Ed25519 private key " + id +
                             " (32-byte seed, hex). Keep it secret: whoever holds it can sign "
                             "firmware that boards trusting its key will run.\n" +
                             Hex(key.seed().data(), 32) + "\n";
  const bool written =
      fchmod(fd, 0600) == 0 &&
      write(fd, secret.data(), secret.size()) == static_cast<ssize_t>(secret.size()) &&
      fsync(fd) == 0;
  const int saved = errno;
  close(fd);
  if (!written) {
    unlink(private_path.c_str());
    return Result<std::string>(Status::kIoError, private_path + ": " + std::strerror(saved));
  }
  const Outcome written_public =
      WriteFileWhole(public_path, "# palpa Ed25519 public key " + id + " (hex)\n" +
                                      Hex(key.PublicKey(), 32) + "\n");
  if (!written_public.ok()) {
    unlink(private_path.c_str());
    return Result<std::string>(written_public);
  }
  return id;
}

}  // namespace palpa::host
