// The simulated board's flash kept in a file (palpa-sim --flash FILE), so what a board keeps
// across a power cycle — configuration, boot state, firmware slots — outlives the process.
#pragma once

#include <string>

#include "palpa/hal/fake/simulated_nor_flash.h"
#include "palpa/hal/flash.h"
#include "palpa/hal/linux/opened.h"

namespace palpa::sim {

using protocol::Status;

/// Every erase and program goes to the simulated flash and then, as it left the flash (torn
/// writes included), to the file at once: a palpa-sim that is killed loses nothing it wrote.
class FlashFile final : public hal::Flash {
 public:
  explicit FlashFile(hal::fake::SimulatedNorFlash& flash) : flash_(flash) {}
  ~FlashFile();
  FlashFile(const FlashFile&) = delete;
  FlashFile& operator=(const FlashFile&) = delete;

  /// Opens PATH for a board with configuration `config`. An existing file's contents replace the
  /// flash's (a file of another configuration or size is refused, naming both); a new file gets
  /// the flash as it is now (the factory's). Refused, the message starting "--flash PATH: ",
  /// with kIoError (cannot be opened or written) or kBadValue (not this board's flash file).
  hal::Done Open(const std::string& path, const std::string& config);
  /// True when Open found the file there already (the board has been powered before).
  bool existed() const { return existed_; }

 private:
  Status DoErase(uint32_t offset) override;
  Status DoProgram(uint32_t offset, const uint8_t* data, size_t size) override;
  Status DoRead(uint32_t offset, uint8_t* out, size_t size) override;
  uint32_t DoSectorSize() const override { return flash_.sector_size(); }
  uint32_t DoSize() const override { return flash_.size(); }
  /// Writes flash bytes [offset, offset + size) to the file; kIoError when it cannot.
  Status Persist(uint32_t offset, size_t size);

  hal::fake::SimulatedNorFlash& flash_;
  int fd_ = -1;
  bool existed_ = false;
};

}  // namespace palpa::sim
