// Type-id lookup over the catalog.
#include "palpa/protocol/catalog.h"

#include <array>

namespace palpa::protocol {
namespace {

constexpr std::array<MessageInfo, Catalog::kSize> MakeInfoTable() {
  std::array<MessageInfo, Catalog::kSize> table{};
  size_t i = 0;
  ForEachMessage(Catalog{}, [&]<class M>() { table[i++] = M::kInfo; });
  return table;
}

constexpr auto kInfoTable = MakeInfoTable();

constexpr bool TypesUnique() {
  for (size_t i = 0; i < kInfoTable.size(); ++i) {
    for (size_t j = i + 1; j < kInfoTable.size(); ++j) {
      if (kInfoTable[i].type == kInfoTable[j].type) return false;
    }
  }
  return true;
}
static_assert(TypesUnique(), "two messages share a type id");

}  // namespace

const MessageInfo* FindMessageInfo(uint8_t type) {
  for (const MessageInfo& info : kInfoTable) {
    if (static_cast<uint8_t>(info.type) == type) return &info;
  }
  return nullptr;
}

}  // namespace palpa::protocol
