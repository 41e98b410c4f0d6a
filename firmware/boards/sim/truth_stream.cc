// Truth as JSON lines to a file or a TCP reader.
#include "truth_stream.h"

#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "tcp_listener.h"

namespace palpa::sim {

TruthStream::~TruthStream() {
  if (client_fd_ >= 0) close(client_fd_);
  if (listen_fd_ >= 0) close(listen_fd_);
}

hal::Done TruthStream::Open(const std::string& spec) {
  if (spec.rfind("file:", 0) == 0) {
    const hal::Done opened = file_.Open(spec.substr(5));
    if (!opened.ok()) return {opened.status, "--truth " + opened.message};
    address_ = spec;
    return {};
  }
  std::string why;  // the hosted boards' listener says it in words
  listen_fd_ = hosted::ListenTcp(spec, "--truth", &address_, &why);
  if (listen_fd_ < 0) return {hal::Status::kUnavailable, why};
  return {};
}

hal::Done TruthStream::Close() {
  if (!file_.is_open()) return {};
  const hal::Done committed = file_.Commit();
  if (!committed.ok()) return {committed.status, "--truth " + committed.message};
  return {};
}

void TruthStream::Pump() {
  if (listen_fd_ < 0 || client_fd_ >= 0) return;
  client_fd_ = accept(listen_fd_, nullptr, nullptr);
}

std::string TruthStream::Format(const PlantTruth& truth, uint64_t board_time_us,
                                const BoardFacts& board) {
  char buffer[160];
  std::string line = "{\"board_time_us\":" + std::to_string(board_time_us) +
                     ",\"board\":{\"safe\":" + (board.safe ? "true" : "false") +
                     ",\"faults\":" + std::to_string(board.faults) +
                     ",\"last_host_frame_us\":" + std::to_string(board.last_host_frame_us) +
                     "},\"lines\":[";
  for (size_t i = 0; i < truth.lines.size(); ++i) {
    const LineTruth& l = truth.lines[i];
    std::snprintf(buffer, sizeof(buffer),
                  "%s{\"command_pa\":%.1f,\"outlet_pa\":%.1f,\"chamber_pa\":%.1f}", i ? "," : "",
                  l.command_pa, l.outlet_pa, l.chamber_pa);
    line += buffer;
  }
  line += "],\"fingers\":[";
  for (size_t i = 0; i < truth.fingers.size(); ++i) {
    const FingerTruth& f = truth.fingers[i];
    if (f.jamming) {
      std::snprintf(buffer, sizeof(buffer), "%s{\"stiffness_n_per_mm\":%.5f}", i ? "," : "",
                    f.stiffness_n_per_mm);
    } else {
      std::snprintf(buffer, sizeof(buffer), "%s{\"deformation_mm\":%.5f}", i ? "," : "",
                    f.deformation_mm);
    }
    line += buffer;
  }
  return line + "]}";
}

void TruthStream::Write(const PlantTruth& truth, uint64_t board_time_us, const BoardFacts& board) {
  const std::string line = Format(truth, board_time_us, board) + "\n";
  if (file_.is_open()) file_.Write(line);
  if (client_fd_ >= 0) {
    const ssize_t n = send(client_fd_, line.data(), line.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK) {
      close(client_fd_);
      client_fd_ = -1;
    }
  }
}

}  // namespace palpa::sim
