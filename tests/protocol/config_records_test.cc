// Configuration records: the bytes of a record, walking a blob, and every way a blob is cut short.
#include <cstring>
#include <string>
#include <vector>

#include "config_record.h"
#include "palpa/protocol/config_records.h"

#include "CppUTest/TestHarness.h"

namespace pp = palpa::protocol;

namespace {

template <class M>
void Append(std::vector<uint8_t>& blob, const M& m) {
  CHECK(palpa::testing::AppendConfigRecord(blob, m));
}
}  // namespace

TEST_GROUP(ConfigRecords){};

TEST(ConfigRecords, ARecordIsItsBodyLengthLittleEndianItsTypeAndItsBody) {
  pp::ConfigureBoard board{};
  board.host_timeout_us = 123456;
  uint8_t body[512];
  const auto body_size = pp::EncodeBody(board, body, sizeof(body));
  CHECK(body_size.ok());
  uint8_t record[pp::kRecordHeaderSize + 512];
  const auto n = pp::EncodeRecord(board, record, sizeof(record));
  CHECK(n.ok());
  LONGS_EQUAL(3 + body_size.value, n.value);
  LONGS_EQUAL(body_size.value & 0xFF, record[0]);
  LONGS_EQUAL(body_size.value >> 8, record[1]);
  LONGS_EQUAL(static_cast<uint8_t>(pp::MessageType::kConfigureBoard), record[2]);
  MEMCMP_EQUAL(body, record + 3, body_size.value);
}

TEST(ConfigRecords, ARecordThatDoesNotFitIsAnOverflow) {
  uint8_t record[16];
  LONGS_EQUAL(static_cast<int>(pp::Status::kOverflow),
              static_cast<int>(pp::EncodeRecord(pp::ConfigureBoard{}, record, 2).status));
  LONGS_EQUAL(
      static_cast<int>(pp::Status::kOverflow),
      static_cast<int>(pp::EncodeRecord(pp::ConfigureBoard{}, record, sizeof(record)).status));
}

TEST(ConfigRecords, TheReaderGivesBackEachRecordInOrder) {
  std::vector<uint8_t> blob;
  pp::ConfigureBoard first{}, second{};
  first.host_timeout_us = 77000;
  second.host_timeout_us = 88000;
  Append(blob, first);
  Append(blob, second);
  pp::RecordReader reader(blob.data(), blob.size());
  for (uint32_t expected : {77000u, 88000u}) {
    pp::Record r;
    CHECK(!reader.done());
    CHECK(reader.Next(r) == pp::Status::kOk);
    LONGS_EQUAL(static_cast<uint8_t>(pp::MessageType::kConfigureBoard), r.type);
    pp::ConfigureBoard decoded{};
    CHECK(pp::DecodeBody(r.body, r.size, decoded) == pp::Status::kOk);
    LONGS_EQUAL(expected, decoded.host_timeout_us);
  }
  LONGS_EQUAL(2, reader.index());
  CHECK(reader.done());
}

TEST(ConfigRecords, AnEmptyBlobHasNoRecords) {
  pp::RecordReader reader(nullptr, 0);
  CHECK(reader.done());
}

TEST(ConfigRecords, AHeaderCutShortIsRefusedWithItsReason) {
  std::vector<uint8_t> blob;
  Append(blob, pp::ConfigureBoard{});
  const size_t whole = blob.size();
  blob.push_back(5);  // one byte of the next record's header
  pp::RecordReader reader(blob.data(), blob.size());
  pp::Record r;
  CHECK(reader.Next(r) == pp::Status::kOk);
  CHECK(!reader.done());
  const char* reason = "";
  CHECK(reader.Next(r, &reason) == pp::Status::kBadLength);
  STRCMP_EQUAL("truncated record header", reason);
  CHECK(reader.done());  // the walk ends there
  LONGS_EQUAL(whole + 1, blob.size());
}

TEST(ConfigRecords, ABodyCutShortIsRefusedWithItsReason) {
  std::vector<uint8_t> blob;
  Append(blob, pp::ConfigureBoard{});
  blob.pop_back();
  pp::RecordReader reader(blob.data(), blob.size());
  pp::Record r;
  const char* reason = "";
  CHECK(reader.Next(r, &reason) == pp::Status::kBadLength);
  STRCMP_EQUAL("record longer than the blob", reason);
  CHECK(reader.done());
}
