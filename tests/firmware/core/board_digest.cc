// The board's behaviour digest: scripts from a fixed seed (board_script_generator.h) run through
// the whole board on the fakes (board_script.h, with the board fuzzer's checks), hashing after
// every loop pass whether it ticked, the time, the DAC codes, each configured line's status bits,
// the latched faults and active conditions, supply and dump valves, pump, session and safe
// state, and every byte the board sent. A change that means to keep behaviour keeps the digest.
//
//   board_digest FILE           compares with the stored digest (exit 1 on any difference)
//   board_digest --bless FILE   writes the digest (a change that means to alter behaviour)
//   board_digest --trace N      script N's loop passes, one line each (diff two builds' output)
//   board_digest --stats        what the scripts exercised: the board's answers by message type
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "board_script.h"
#include "board_script_generator.h"
#include "palpa/protocol/catalog.h"
#include "palpa/protocol/sha256.h"

namespace {

namespace pp = palpa::protocol;
using palpa::testing::BoardHarness;
using palpa::testing::BoardScript;

constexpr uint64_t kSeed = 0x5A1FA0D16E57ull;
constexpr unsigned kScripts = 128;

std::string Hex(const uint8_t* data, size_t size) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s;
  for (size_t i = 0; i < size; ++i) {
    s += kDigits[data[i] >> 4];
    s += kDigits[data[i] & 15];
  }
  return s;
}

/// What one loop pass leaves observable, as bytes (little-endian).
std::vector<uint8_t> Observe(const BoardHarness& h, bool ticked, const uint8_t* sent, size_t n) {
  std::vector<uint8_t> r;
  auto put32 = [&r](uint32_t v) {
    for (int i = 0; i < 4; ++i) r.push_back(static_cast<uint8_t>(v >> (8 * i)));
  };
  r.push_back(ticked);
  put32(static_cast<uint32_t>(h.clock.now_us));
  put32(static_cast<uint32_t>(h.clock.now_us >> 32));
  for (uint32_t code : h.dac.counts) put32(code);
  const uint8_t lines = h.board->config().line_count;
  r.push_back(lines);
  for (uint8_t i = 0; i < lines; ++i) r.push_back(h.board->line_output(i).status);
  put32(h.board->latched_faults());
  put32(h.board->active_conditions());
  r.push_back(static_cast<uint8_t>(h.supply.level | h.dump.level << 1 | h.pump.level << 2 |
                                   h.board->session_open() << 3 | h.board->safe() << 4));
  put32(static_cast<uint32_t>(n));
  r.insert(r.end(), sent, sent + n);
  return r;
}

struct Digest {
  std::vector<std::string> scripts;
  std::string all;
};

Digest Compute() {
  palpa::testing::BoardScriptGenerator generator(kSeed);
  pp::Sha256Hasher all;
  Digest d;
  for (unsigned k = 0; k < kScripts; ++k) {
    const std::vector<uint8_t> script = generator.Next();
    pp::Sha256Hasher hasher;
    BoardScript(script.data(), script.size(),
                [&](const BoardHarness& h, bool ticked, const uint8_t* sent, size_t n) {
                  const std::vector<uint8_t> r = Observe(h, ticked, sent, n);
                  hasher.Update(r.data(), r.size());
                })
        .Run();
    const pp::Sha256Digest one = hasher.Finish();
    all.Update(one.data(), one.size());
    d.scripts.push_back(Hex(one.data(), one.size()));
  }
  const pp::Sha256Digest total = all.Finish();
  d.all = Hex(total.data(), total.size());
  return d;
}

std::string Format(const Digest& d) {
  std::ostringstream out;
  out << "# The board's behaviour digest (tests/firmware/core/board_digest.cc): " << kScripts
      << " scripts from seed 0x" << std::hex << kSeed << std::dec << ".\n"
      << "# Re-bless only for a change meant to alter behaviour: docs/firmware.md says how.\n";
  for (size_t k = 0; k < d.scripts.size(); ++k)
    out << "script " << k << " " << d.scripts[k] << "\n";
  out << "all " << d.all << "\n";
  return out.str();
}

int Check(const char* path) {
  std::ifstream in(path);
  if (!in) {
    std::fprintf(stderr, "board_digest: cannot read %s\n", path);
    return 1;
  }
  std::stringstream stored;
  stored << in.rdbuf();
  const Digest d = Compute();
  const std::string now = Format(d);
  if (now == stored.str()) {
    std::printf("board digest: %u scripts, all %s: as stored\n", kScripts, d.all.c_str());
    return 0;
  }
  std::istringstream lines(stored.str());
  std::string line;
  unsigned differing = 0;
  while (std::getline(lines, line)) {
    unsigned k = 0;
    char hex[65] = {};
    if (std::sscanf(line.c_str(), "script %u %64s", &k, hex) != 2) continue;
    if (k < d.scripts.size() && d.scripts[k] == hex) continue;
    if (differing++ < 12)
      std::fprintf(stderr,
                   "board digest: script %u behaves differently (board_digest --trace %u)\n", k, k);
  }
  std::fprintf(stderr,
               "board digest: %u of %u scripts differ from %s (all %s now).\n"
               "A change meant to keep behaviour changed it; one meant to alter it re-blesses "
               "the digest (docs/firmware.md).\n",
               differing, kScripts, path, d.all.c_str());
  return 1;
}

int Bless(const char* path) {
  const std::string text = Format(Compute());
  std::ofstream out(path, std::ios::trunc);
  out << text;
  if (!out.flush()) {
    std::fprintf(stderr, "board_digest: cannot write %s\n", path);
    return 1;
  }
  std::printf("board digest: written to %s\n", path);
  return 0;
}

int Trace(unsigned wanted) {
  palpa::testing::BoardScriptGenerator generator(kSeed);
  std::vector<uint8_t> script;
  for (unsigned k = 0; k <= wanted; ++k) script = generator.Next();
  unsigned pass = 0;
  BoardScript(script.data(), script.size(),
              [&](const BoardHarness& h, bool ticked, const uint8_t* sent, size_t n) {
                const std::vector<uint8_t> r = Observe(h, ticked, sent, n);
                std::printf("%u %s\n", pass++, Hex(r.data(), r.size()).c_str());
              })
      .Run();
  return 0;
}

/// The board's answers over every script, by message type: Ack, Nack by status, or a report.
int Stats() {
  palpa::testing::BoardScriptGenerator generator(kSeed);
  std::map<std::string, unsigned> counts;
  unsigned passes = 0, ticks = 0, actuating = 0;
  for (unsigned k = 0; k < kScripts; ++k) {
    const std::vector<uint8_t> script = generator.Next();
    pp::OwningFrameDecoder decoder;
    BoardScript(script.data(), script.size(),
                [&](const BoardHarness& h, bool ticked, const uint8_t* sent, size_t n) {
                  ++passes;
                  ticks += ticked;
                  actuating += ticked && !h.board->safe();
                  for (unsigned bit = 0; bit < static_cast<unsigned>(pp::Fault::kCount); ++bit) {
                    if (ticked && (h.board->latched_faults() >> bit & 1) != 0)
                      ++counts[std::string("(ticks latched) ") + pp::kFaultNames[bit]];
                  }
                  if (ticked && h.board->safe() && h.board->latched_faults() == 0)
                    ++counts[h.board->session_open() ? "(ticks safe) session open, no fault"
                                                     : "(ticks safe) no session, no fault"];
                  for (size_t i = 0; i < n; ++i) {
                    if (decoder.Process(sent[i]) != pp::FrameDecoder::Event::kFrame) continue;
                    const pp::Frame& f = decoder.frame();
                    const palpa::testing::ReceivedFrame r{
                        f.header, std::vector<uint8_t>(f.body, f.body + f.body_size)};
                    auto name = [](uint8_t type) {
                      const pp::MessageInfo* info = pp::FindMessageInfo(type);
                      return std::string(info != nullptr ? info->name : "?");
                    };
                    if (r.Is<pp::Ack>()) {
                      ++counts[name(r.As<pp::Ack>().acked_type) + " ok"];
                    } else if (r.Is<pp::Nack>()) {
                      const pp::Nack nack = r.As<pp::Nack>();
                      ++counts[name(nack.refused_type) + " " + pp::StatusName(nack.status)];
                    } else {
                      ++counts["(report) " + name(f.header.type)];
                    }
                  }
                })
        .Run();
  }
  std::printf("%u scripts, %u loop passes, %u ticks (%u of them actuating)\n", kScripts, passes,
              ticks, actuating);
  for (const auto& [what, n] : counts) std::printf("  %-40s %u\n", what.c_str(), n);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::strcmp(argv[1], "--stats") == 0) return Stats();
  if (argc == 3 && std::strcmp(argv[1], "--trace") == 0) return Trace(std::stoul(argv[2]));
  if (argc == 3 && std::strcmp(argv[1], "--bless") == 0) return Bless(argv[2]);
  if (argc == 2 && argv[1][0] != '-') return Check(argv[1]);
  std::fprintf(stderr, "usage: board_digest FILE | --bless FILE | --trace N | --stats\n");
  return 2;
}
