// The link's recovery at full size: 10 000 reliable commands through a transport that drops 1 %
// of bytes and flips bits in 0.1 %, to an in-process test board; exactly once and in order.
#include <chrono>
#include <cstdio>

#include "board_transport.h"
#include "palpa/host/fault_transport.h"
#include "palpa/host/link.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

int main() {
  palpa::testing::TestBoard board(pp::kCatalogHash, 1024, 21);
  ph::FaultSpec faults;
  faults.drop = 0.01;
  faults.bit_flip = 0.001;
  auto link =
      ph::Link::Open(std::make_unique<ph::FaultTransport>(
                         std::make_unique<palpa::testing::BoardTransport>(board), faults, 9),
                     ph::LinkOptions{});
  if (!link.ok()) {
    std::fprintf(stderr, "%s\n", link.message.c_str());
    return 1;
  }
  const int n = 10000;
  int failed = 0;
  const auto start = std::chrono::steady_clock::now();
  for (uint32_t id = 1; id <= static_cast<uint32_t>(n); ++id)
    failed += link.value->Command(pp::ClearFault{id}).status != pp::Status::kOk;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  bool in_order = board.applied.size() == static_cast<size_t>(n);
  for (size_t i = 0; in_order && i < board.applied.size(); ++i)
    in_order = board.applied[i].command_id == i + 1;
  const auto c = link.value->counters();
  std::printf("== link under faults: %d reliable commands, 1 %% byte loss + 0.1 %% bit flips ==\n",
              n);
  std::printf("  applied exactly once and in order: %s (%zu applied, %d failed)\n",
              in_order ? "yes" : "NO", board.applied.size(), failed);
  std::printf("  retransmissions %llu, framing errors seen %llu, %.0f commands/s\n",
              static_cast<unsigned long long>(c.retransmissions),
              static_cast<unsigned long long>(c.framing_errors), n / s);
  return in_order && failed == 0 ? 0 : 1;
}
