// The gadget's three interfaces as one byte link: FunctionFS bulk and HID endpoints through native
// AIO, the ACM port as a tty, and the board's output routed to the interface in use.
#include "gadget_link.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "aio.h"
#include "ffs_endpoints.h"
#include "ffs_function.h"
#include "gadget_claim.h"
#include "hid_requests.h"
#include "process_claim.h"
#include "usb_descriptors.h"

namespace palpa::gadget {
namespace {

enum EndpointId : uint32_t { kBulkIn = 1, kBulkOut, kHidIn, kHidOut };
// Endpoint files are numbered in descriptor order: IN first, then OUT.
constexpr int kInFile = 0, kOutFile = 1;
// A host polls the HID input endpoint once per 1 ms frame (bInterval 1) and takes at most one
// report each time. dummy_hcd ignores the interval and would take reports as fast as they come,
// so the gadget keeps to the schedule itself: one report in flight, one a millisecond. A report
// that misses its frame waits for the next, as on the bus.
constexpr int64_t kReportIntervalNs = 1000000;
// One bulk IN transfer at a time, carrying all that queued while the previous one was on the bus:
// a host's read completes at the first short packet, so many small transfers would cost a bus
// frame each. A length that is not a multiple of the 64-byte packet ends with a short packet,
// which completes the host's read without waiting for a zero-length packet.
constexpr size_t kBulkInTransfer = 4095;

int64_t NowNs() {
  timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<int64_t>(t.tv_sec) * 1000000000 + t.tv_nsec;
}

}  // namespace

struct GadgetLink::Impl {
  hosted::ProcessClaim claim;
  ConfigfsGadget gadget;
  AioContext aio;
  FfsFunction bulk, hid;
  bool has_bulk = false, has_hid = false;
  OutEndpoint bulk_out{kBulkOut, 8, kBulkPacketBytes};
  InEndpoint bulk_in{kBulkIn, 1, kBulkInTransfer};
  OutEndpoint hid_out{kHidOut, 2, kHidReportBytes};
  InEndpoint hid_in{kHidIn, 1, kHidReportBytes};
  int acm = -1;
  int64_t next_report_ns = 0;
  std::vector<uint8_t> arrived;
};

GadgetLink::GadgetLink() : impl_(new Impl) {}

GadgetLink::~GadgetLink() { Close(); }

bool GadgetLink::Open(const GadgetLinkOptions& o, std::string* error) {
  Impl& m = *impl_;
  mkdir(o.mount_root.c_str(), 0755);
  // The name is claimed first: a gadget of that name is then one a dead owner left (kill -9 leaves
  // it in configfs, its FunctionFS instances mounted), taken down before this one is made; a
  // living owner keeps it and this Open fails.
  if (!m.aio.Open(64, error) ||
      !m.claim.Take(o.mount_root + "/" + o.name + ".lock", "gadget " + o.name, error) ||
      !RemoveStaleGadget(o.name, &stale_removed_, error) ||
      !m.gadget.Create(o.name, o.identity, error))
    return false;
  // Each FunctionFS function: its instance in configfs, then its file system and descriptors.
  auto add_ffs = [&](const char* suffix, FfsFunction& f, const std::vector<uint8_t>& descriptors,
                     const char* interface_name) {
    const std::string instance = o.name + suffix;
    return m.gadget.AddFunction("ffs." + instance, error) &&
           f.Open(instance, o.mount_root + "/" + instance, descriptors,
                  InterfaceStrings(interface_name), 2, error);
  };
  if (o.bulk) {
    if (!add_ffs("_bulk", m.bulk, VendorBulkDescriptors(), "palpa link (vendor bulk)"))
      return false;
    m.has_bulk = true;
  }
  if (o.hid) {
    if (!add_ffs("_hid", m.hid, HidDescriptors(), "palpa link (HID)")) return false;
    m.hid.set_setup_handler(HidSetup);
    m.has_hid = true;
  }
  if (o.acm) {
    const std::string instance = "acm." + o.name;
    if (!m.gadget.AddFunction(instance, error)) return false;
    acm_device_ = "/dev/ttyGS" + m.gadget.FunctionAttribute(instance, "port_num");
    if (!OpenAcm()) {
      *error = acm_device_ + ": " + std::strerror(errno);
      return false;
    }
  }
  return m.gadget.Bind(o.udc, error);
}

void GadgetLink::Close() {
  if (!impl_) return;
  Impl& m = *impl_;
  m.gadget.Unbind();
  if (m.acm >= 0) close(m.acm);
  m.acm = -1;
  m.bulk.Close();
  m.hid.Close();
  m.gadget.Remove();
  m.claim.Release();
  m.has_bulk = m.has_hid = false;
  active_ = Channel::kNone;
}

const std::string& GadgetLink::configfs_path() const { return impl_->gadget.path(); }
const std::string& GadgetLink::udc() const { return impl_->gadget.udc(); }

void GadgetLink::Pump() {
  Impl& m = *impl_;
  if (m.has_bulk && m.bulk.ServiceEp0()) {
    if (m.bulk.enabled()) {
      m.bulk_out.Start(m.aio, m.bulk.endpoint_fd(kOutFile));
    } else {
      Deactivate(Channel::kBulk);
    }
  }
  if (m.has_hid && m.hid.ServiceEp0()) {
    if (m.hid.enabled()) {
      m.hid_out.Start(m.aio, m.hid.endpoint_fd(kOutFile));
    } else {
      Deactivate(Channel::kHid);
    }
  }
  m.aio.Reap([&](uint64_t tag, int64_t result) {
    const uint32_t slot = TagSlot(tag);
    m.arrived.clear();
    switch (TagEndpoint(tag)) {
      case kBulkOut:
        m.bulk_out.Complete(slot, result, m.aio, m.bulk.endpoint_fd(kOutFile), m.bulk.enabled(),
                            m.arrived);
        FromHost(Channel::kBulk, m.arrived.data(), m.arrived.size());
        break;
      case kHidOut:
        m.hid_out.Complete(slot, result, m.aio, m.hid.endpoint_fd(kOutFile), m.hid.enabled(),
                           m.arrived);
        FromHost(Channel::kHid, m.arrived.data(), m.arrived.size());
        break;
      case kBulkIn:
        counters_.bytes_to_host[static_cast<int>(Channel::kBulk)] +=
            m.bulk_in.Complete(slot, result);
        break;
      case kHidIn:
        if (m.hid_in.Complete(slot, result) > 0) ++counters_.hid_reports;
        break;
      default:
        break;
    }
  });
  if (m.acm < 0 && !acm_device_.empty()) OpenAcm();
  if (m.acm >= 0) {
    uint8_t buffer[512];
    ssize_t n;
    while ((n = read(m.acm, buffer, sizeof(buffer))) > 0)
      FromHost(Channel::kAcm, buffer, static_cast<size_t>(n));
    if (n == 0 || (n < 0 && errno != EAGAIN)) {
      // The host went away (unbound, unplugged): the gadget's tty was hung up and stays dead;
      // a new open serves the next connection.
      close(m.acm);
      m.acm = -1;
      Deactivate(Channel::kAcm);
    }
  }
  Transmit();
}

bool GadgetLink::OpenAcm() {
  Impl& m = *impl_;
  m.acm = open(acm_device_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (m.acm < 0) return false;
  termios raw{};  // the gadget's tty echoes and edits lines unless told otherwise
  tcgetattr(m.acm, &raw);
  cfmakeraw(&raw);
  tcsetattr(m.acm, TCSANOW, &raw);
  return true;
}

void GadgetLink::FromHost(Channel channel, const uint8_t* data, size_t size) {
  if (size == 0) return;
  counters_.bytes_from_host[static_cast<int>(channel)] += size;
  if (channel != active_) {  // a host on another interface: what was queued was for the old one
    counters_.dropped += tx_.size();
    tx_.clear();
    active_ = channel;
  }
  rx_.insert(rx_.end(), data, data + size);
}

void GadgetLink::Deactivate(Channel channel) {
  if (active_ != channel) return;
  counters_.dropped += tx_.size();
  tx_.clear();
  active_ = Channel::kNone;
}

void GadgetLink::Transmit() {
  Impl& m = *impl_;
  size_t sent = 0;
  switch (active_) {
    case Channel::kBulk:
      while (m.bulk.enabled() && m.bulk_in.CanSend() && sent < tx_.size()) {
        size_t n = std::min(tx_.size() - sent, kBulkInTransfer);
        if (n % kBulkPacketBytes == 0) --n;
        if (!m.bulk_in.Send(m.aio, m.bulk.endpoint_fd(kInFile), tx_.data() + sent, n)) break;
        sent += n;
      }
      break;
    case Channel::kHid: {
      // What the buffer holds at each poll, up to a report, zero padded (read as empty frames).
      const int64_t now = NowNs();
      while (m.hid.enabled() && m.hid_in.CanSend() && sent < tx_.size() &&
             now >= m.next_report_ns) {
        uint8_t report[kHidReportBytes] = {};
        const size_t n = std::min(tx_.size() - sent, kHidReportBytes);
        std::memcpy(report, tx_.data() + sent, n);
        if (!m.hid_in.Send(m.aio, m.hid.endpoint_fd(kInFile), report, sizeof(report))) break;
        sent += n;
        counters_.bytes_to_host[static_cast<int>(Channel::kHid)] += n;
        // Frames keep their schedule: a wake-up late within a frame does not delay the next.
        m.next_report_ns = std::max(m.next_report_ns + kReportIntervalNs, now);
      }
      break;
    }
    case Channel::kAcm: {
      const ssize_t n = m.acm >= 0 ? write(m.acm, tx_.data(), tx_.size()) : -1;
      if (n > 0) {
        sent = static_cast<size_t>(n);
        counters_.bytes_to_host[static_cast<int>(Channel::kAcm)] += sent;
      }
      break;
    }
    default:
      break;
  }
  tx_.erase(tx_.begin(), tx_.begin() + static_cast<long>(sent));
}

std::vector<pollfd> GadgetLink::PollFds() const {
  const Impl& m = *impl_;
  std::vector<pollfd> fds{{m.aio.poll_fd(), POLLIN, 0}};
  if (m.has_bulk) fds.push_back({m.bulk.ep0_fd(), POLLIN, 0});
  if (m.has_hid) fds.push_back({m.hid.ep0_fd(), POLLIN, 0});
  if (m.acm >= 0) {
    const bool sending = active_ == Channel::kAcm && !tx_.empty();
    fds.push_back({m.acm, static_cast<short>(POLLIN | (sending ? POLLOUT : 0)), 0});
  }
  return fds;
}

int GadgetLink::PollTimeoutMs() const {
  const Impl& m = *impl_;
  if (active_ != Channel::kHid || tx_.empty() || !m.hid_in.CanSend()) return -1;
  const int64_t wait = m.next_report_ns - NowNs();
  return wait <= 0 ? 0 : static_cast<int>((wait + 999999) / 1000000);
}

size_t GadgetLink::DoRead(uint8_t* out, size_t capacity) {
  const size_t n = std::min(capacity, rx_.size() - rx_read_);
  std::memcpy(out, rx_.data() + rx_read_, n);
  rx_read_ += n;
  if (rx_read_ == rx_.size()) {
    rx_.clear();
    rx_read_ = 0;
  }
  return n;
}

size_t GadgetLink::DoWrite(const uint8_t* data, size_t size) {
  if (active_ == Channel::kNone) {  // no host: the bytes go nowhere, as on an unplugged cable
    counters_.dropped += size;
    return size;
  }
  const size_t n = std::min(size, DoWriteSpace());
  tx_.insert(tx_.end(), data, data + n);
  return n;
}

size_t GadgetLink::DoWriteSpace() const {
  if (active_ == Channel::kNone) return kTxCapacity;
  return tx_.size() < kTxCapacity ? kTxCapacity - tx_.size() : 0;
}

}  // namespace palpa::gadget
