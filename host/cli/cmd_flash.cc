// palpa flash and palpa package: updating a board's firmware over its link, and making the
// update package (both slot builds of one release) from the slots' binaries.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <thread>

#include "cli.h"
#include "palpa/hal/linux/gpio_output.h"
#include "palpa/host/boot_pins.h"
#include "palpa/host/file_write.h"
#include "palpa/host/flasher.h"
#include "palpa/host/signing_key.h"
#include "progress_bar.h"

namespace palpa::cli {
namespace {

namespace pp = protocol;

/// A whole file within its kind's limit, or why not (naming the file).
host::Result<std::vector<uint8_t>> ReadBytes(const std::string& path,
                                             const host::FileLimits& limits) {
  const auto text = host::ReadFileWhole(path, limits);
  if (!text.ok()) return text.outcome();
  return std::vector<uint8_t>(text.value.begin(), text.value.end());
}

void Progress(const host::FlashProgress& p) {
  static ProgressBar bar;  // the write's; the steps after it get a line each
  if (p.step != "write") {
    if (p.done == p.total) {
      bar.End();
      std::fprintf(stderr, "  %s\n", p.step.c_str());
    }
    return;
  }
  const int percent = p.total > 0 ? static_cast<int>(100.0 * p.done / p.total) : 100;
  const double rate = p.seconds > 0 ? p.done / p.seconds / 1024 : 0;
  char text[96];
  std::snprintf(text, sizeof(text), "%3d %%  %u/%u bytes  %.1f KiB/s", percent, p.done, p.total,
                rate);
  bar.Show(p.done, p.total, text);
}

/// "1.2.3" into its parts; false when malformed.
bool ParseVersion(const std::string& text, uint8_t* major, uint8_t* minor, uint16_t* patch) {
  unsigned a = 0, b = 0, c = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%u.%u.%u%c", &a, &b, &c, &tail) != 3 || a > 255 || b > 255 ||
      c > 65535)
    return false;
  *major = static_cast<uint8_t>(a);
  *minor = static_cast<uint8_t>(b);
  *patch = static_cast<uint16_t>(c);
  return true;
}

}  // namespace

int CmdFlash(Context& c, const std::vector<std::string>& args) {
  std::string package_path, reset_spec, boot_spec;
  host::FlashOptions options;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--resume") {
      options.resume = true;
    } else if (a == "--dry-run") {
      options.dry_run = true;
    } else if (a == "--allow-downgrade") {
      options.allow_downgrade = true;
    } else if (a == "--allow-counter-jump") {
      options.allow_counter_jump = true;
    } else if (a == "--reset-line" || a == "--boot-line") {
      if (i + 1 >= args.size()) return Usage("flash", a + " needs CHIP:LINE");
      (a == "--reset-line" ? reset_spec : boot_spec) = args[++i];
    } else if (!a.empty() && a[0] == '-') {
      return Usage("flash", "unexpected option '" + a + "'");
    } else if (package_path.empty()) {
      package_path = a;
    } else {
      return Usage("flash", "unexpected argument '" + a + "' (one package at a time)");
    }
  }
  if (package_path.empty()) return Usage("flash", "needs a PACKAGE (made by palpa package)");
  const auto bytes = ReadBytes(package_path, host::kPackageFileLimits);
  if (!bytes.ok()) return Usage("flash", bytes.message);
  const auto package = host::ReadPackage(bytes.value);
  if (!package.ok()) return Usage("flash", package_path + ": " + package.message);

  // Boards whose application cannot take the update: their bootloader, by the pins.
  std::unique_ptr<hal::linux_gpio::GpioOutput> reset_pin, boot_pin;
  if (!reset_spec.empty()) {
    auto opened = hal::linux_gpio::GpioOutput::Open(reset_spec, true);
    if (!opened.ok()) return Usage("flash", "--reset-line " + opened.message);
    reset_pin = std::move(opened.value);
  }
  if (!boot_spec.empty()) {
    auto opened = hal::linux_gpio::GpioOutput::Open(boot_spec, false);
    if (!opened.ok()) return Usage("flash", "--boot-line " + opened.message);
    boot_pin = std::move(opened.value);
  }
  host::BootPins pins(reset_pin.get(), boot_pin.get(),
                      [](int ms) { std::this_thread::sleep_for(std::chrono::milliseconds(ms)); });
  if (reset_pin || boot_pin) {
    if (!options.dry_run) pins.ResetIntoBootloader();
    options.before_reboot = [&pins] { pins.ReleaseBoot(); };
  }

  host::Device* device = c.Device();
  if (device == nullptr) return kExitConnect;
  const pp::HelloReply before = device->link().board();
  std::fprintf(
      TextOut(), "board %s %u, slot %u running %s\n",
      pp::EnumNames(pp::BoardKind{})[static_cast<size_t>(before.board_kind)], before.board_id,
      before.active_slot,
      host::VersionText(before.firmware_major, before.firmware_minor, before.firmware_patch)
          .c_str());
  options.progress = Progress;
  const host::FlashReport r = host::FlashPackage(device->link(), package.value, options);
  std::fprintf(stderr, "\n");
  if (!r.signer_key_id.empty() && !c.json) {
    std::fprintf(TextOut(),
                 "package %s, anti-rollback counter %u (board's floor %u), signed by key %s\n",
                 r.to_version.c_str(), r.package_counter, r.board_floor, r.signer_key_id.c_str());
  }
  if (r.status != pp::Status::kOk) {
    return Fail("flash", r.status, r.message,
                r.status == pp::Status::kRollbackRefused || r.status == pp::Status::kImageInvalid
                    ? kExitUsage
                    : kExitFailed);
  }
  if (c.json) {
    PrintJson({{"result", r.message},
               {"dry_run", options.dry_run},
               {"signed_by", r.signer_key_id},
               {"counter", r.package_counter},
               {"bytes_written", r.bytes_written},
               {"resumed_from", r.resumed_from},
               {"write_seconds", r.write_seconds}});
    return kExitOk;
  }
  std::printf("%s\n", r.message.c_str());
  if (!options.dry_run) {
    std::printf(
        "  %u bytes written%s in %.2f s (%.1f KiB/s)\n", r.bytes_written,
        r.resumed_from > 0 ? (" (resumed at " + std::to_string(r.resumed_from) + ")").c_str() : "",
        r.write_seconds, r.write_seconds > 0 ? r.bytes_written / r.write_seconds / 1024 : 0.0);
    if (r.resumed_after_session_loss > 0) {
      std::printf(
          "  the board ended the session mid-write %d time(s) (this host was silent past "
          "its timeout); each time the write went on from what the board had\n",
          r.resumed_after_session_loss);
    }
  }
  return kExitOk;
}

int CmdPackage(Context&, const std::vector<std::string>& args) {
  std::string kind_text = "sim", version_text, out, key_path;
  std::vector<std::string> bodies;
  uint32_t counter = 0;
  bool have_counter = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&](std::string& v) {
      if (i + 1 >= args.size()) return false;
      v = args[++i];
      return true;
    };
    std::string v;
    if (a == "--kind") {
      if (!value(kind_text)) return Usage("package", "--kind needs a board kind");
    } else if (a == "--version") {
      if (!value(version_text)) return Usage("package", "--version needs MAJOR.MINOR.PATCH");
    } else if (a == "--counter") {
      double n = 0;
      if (!value(v) || !ParseNumber(v, n) || n < 0 || n > 4294967295.0 || n != std::floor(n))
        return Usage("package", "--counter " + v + ": expected a whole number 0 to 4294967295");
      counter = static_cast<uint32_t>(n);
      have_counter = true;
    } else if (a == "--out") {
      if (!value(out)) return Usage("package", "--out needs a file");
    } else if (a == "--sign") {
      if (!value(key_path)) return Usage("package", "--sign needs a private key file");
    } else if (!a.empty() && a[0] == '-') {
      return Usage("package", "unexpected option '" + a + "'");
    } else {
      bodies.push_back(a);
    }
  }
  if (bodies.size() != 2 || version_text.empty() || !have_counter || out.empty() ||
      key_path.empty())
    return Usage("package",
                 "needs SLOT0.bin SLOT1.bin --version X.Y.Z --counter N --sign KEY --out FILE");
  const auto seed = host::ReadSigningKey(key_path);
  if (!seed.ok()) return Usage("package", "--sign " + seed.message);
  host::Ed25519Signer signer(seed.value);
  host::ImageSpec spec;
  if (!ParseVersion(version_text, &spec.version_major, &spec.version_minor, &spec.version_revision))
    return Usage("package", "--version " + version_text + ": expected MAJOR.MINOR.PATCH");
  bool known = false;
  for (size_t k = 0; k < static_cast<size_t>(pp::BoardKind::kCount); ++k) {
    if (kind_text == pp::EnumNames(pp::BoardKind{})[k]) {
      spec.board_kind = static_cast<pp::BoardKind>(k);
      known = true;
    }
  }
  if (!known)
    return Usage("package", "--kind " + kind_text + ": expected sim, mps2-an386, stm32f4 or linux");
  spec.rollback_counter = counter;
  spec.signer = &signer;
  host::UpdatePackage package;
  for (uint8_t slot = 0; slot < 2; ++slot) {
    auto body = ReadBytes(bodies[slot], host::kSlotBinaryLimits);
    if (!body.ok()) return Usage("package", body.message);
    spec.body = std::move(body.value);
    auto image = host::BuildSlotImage(spec, slot);
    if (!image.ok()) return Usage("package", bodies[slot] + ": " + image.message);
    package.slot_image[slot] = std::move(image.value);
  }
  const std::vector<uint8_t> bytes = host::WritePackage(package);
  const host::Outcome written =
      host::WriteFileWhole(out, {reinterpret_cast<const char*>(bytes.data()), bytes.size()});
  if (!written.ok()) return Fail("package", written.status, written.message);
  if (JsonOutput()) {
    PrintJson({{"package", out},
               {"kind", kind_text},
               {"version", version_text},
               {"counter", counter},
               {"key_id", host::KeyId(signer.PublicKey())},
               {"slot_image_bytes", {package.slot_image[0].size(), package.slot_image[1].size()}}});
    return kExitOk;
  }
  std::printf("%s: %s %s, counter %u, slot images of %zu and %zu bytes, signed by key %s\n",
              out.c_str(), kind_text.c_str(), version_text.c_str(), counter,
              package.slot_image[0].size(), package.slot_image[1].size(),
              host::KeyId(signer.PublicKey()).c_str());
  return kExitOk;
}

const Command kFlashCommand{
    "flash",
    "flash PACKAGE [--resume] [--dry-run] [--allow-downgrade] [--allow-counter-jump]\n"
    "      [--reset-line CHIP:LINE] [--boot-line CHIP:LINE]",
    "Updates the board's firmware over its link: checks the package against the board (its\n"
    "signature, kind, anti-rollback counter) and shows the version change and who signed it\n"
    "(key id). Before writing anything it refuses a lower version at the board's counter unless\n"
    "--allow-downgrade, and a counter more than one above the board's unless\n"
    "--allow-counter-jump (once confirmed, nothing below it can be installed again). It writes\n"
    "the image for the slot the board reports inactive with a progress bar, verifies its\n"
    "SHA-256, activates it (the board checks the signature against its own keys) for one\n"
    "trial boot, waits for the board to answer on it and confirms it. A board reset before "
    "the\n"
    "confirmation returns to the old image. --resume goes on from what the board reports\n"
    "written; --dry-run checks and says what would happen. --reset-line and --boot-line drive\n"
    "GPIO lines (libgpiod) to start a board whose application cannot run in its bootloader's\n"
    "recovery mode (reset active low, boot active high). docs/flashing.md.",
    CmdFlash};

const Command kPackageCommand{
    "package",
    "package SLOT0.bin SLOT1.bin --version X.Y.Z --counter N --sign KEY [--kind KIND] --out FILE",
    "Makes an update package: each slot's binary (linked to run from that slot) gets the "
    "image\n"
    "header, board kind, slot, anti-rollback counter and SHA-256, signed with the private key\n"
    "KEY (palpa keygen; boards take only images signed by a key built into them). KIND: sim\n"
    "(default), mps2-an386, stm32f4.",
    CmdPackage};

}  // namespace palpa::cli
