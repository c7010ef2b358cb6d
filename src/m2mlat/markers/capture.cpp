#include "m2mlat/markers/capture.hpp"

#include <fmt/format.h>
#include <pcap/pcap.h>
#include <poll.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "m2mlat/core/error.hpp"
#include "m2mlat/markers/packet_decode.hpp"

namespace m2mlat::markers {

namespace {

constexpr int kLiveTimeoutMs = 100;  // a live read returns after this long without a packet

// A pcap file's seconds are unsigned 32-bit (to 2106); libpcap hands them on through a signed 32-bit
// field, so a time from 2038-01-19 03:14:08 UTC on arrives negative.
std::int64_t seconds_since_epoch(std::int64_t tv_sec) { return tv_sec < 0 ? tv_sec + (std::int64_t{1} << 32) : tv_sec; }

}  // namespace

struct Capture::Filter {  // a compiled BPF filter, freed with it
  bpf_program program{};
  bool compiled = false;
  ~Filter() {
    if (compiled) pcap_freecode(&program);
  }
};

Capture::Capture(pcap* handle, std::string name, bool live, StampSource source)
    : handle_(handle), name_(std::move(name)), live_(live), source_(source), link_type_(pcap_datalink(handle)) {}

Capture::Capture(Capture&& other) noexcept
    : handle_(std::exchange(other.handle_, nullptr)),
      dumper_(std::exchange(other.dumper_, nullptr)),
      name_(std::move(other.name_)),
      live_(other.live_),
      source_(other.source_),
      link_type_(other.link_type_),
      read_(other.read_),
      filter_(std::move(other.filter_)) {}

Capture& Capture::operator=(Capture&& other) noexcept {
  if (this != &other) {
    close();
    handle_ = std::exchange(other.handle_, nullptr);
    dumper_ = std::exchange(other.dumper_, nullptr);
    name_ = std::move(other.name_);
    live_ = other.live_;
    source_ = other.source_;
    link_type_ = other.link_type_;
    read_ = other.read_;
    filter_ = std::move(other.filter_);
  }
  return *this;
}

Capture::~Capture() { close(); }

void Capture::close() {
  if (dumper_ != nullptr) pcap_dump_close(dumper_);
  if (handle_ != nullptr) pcap_close(handle_);
  dumper_ = nullptr;
  handle_ = nullptr;
}

Capture Capture::open_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw core::Error(errno == ENOENT ? core::ErrorKind::no_input : core::ErrorKind::io,
                      fmt::format("{}: {}", path, std::strerror(errno)));
  char error[PCAP_ERRBUF_SIZE] = "";
  pcap* handle = pcap_open_offline_with_tstamp_precision(path.c_str(), PCAP_TSTAMP_PRECISION_NANO, error);
  if (handle == nullptr)
    throw core::Error(core::ErrorKind::data, fmt::format("{}: not a pcap or pcapng file (libpcap: {})", path, error));
  Capture capture(handle, path, false, StampSource::file);
  if (!is_supported_link_type(capture.link_type_))
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: link type {} is not one m2mlat decodes (Ethernet, Linux cooked SLL or SLL2, "
                                  "raw IP, loopback)",
                                  path, link_type_text(capture.link_type_)));
  return capture;
}

Capture Capture::open_live(const LiveOptions& options) {
  char error[PCAP_ERRBUF_SIZE] = "";
  pcap* handle = pcap_create(options.interface.c_str(), error);
  if (handle == nullptr)
    throw core::Error(core::ErrorKind::io, fmt::format("interface {}: {}", options.interface, error));
  Capture capture(handle, options.interface, true, StampSource::host);
  pcap_set_snaplen(handle, options.snapshot_bytes);
  pcap_set_promisc(handle, 0);
  pcap_set_buffer_size(handle, options.buffer_bytes);
  // Each packet as it comes (no batching in the kernel's ring): the capture's reading is not the
  // measurement (the timestamps are the kernel's), but a short run should see its last packets.
  pcap_set_immediate_mode(handle, 1);
  pcap_set_timeout(handle, kLiveTimeoutMs);
  if (pcap_set_tstamp_precision(handle, PCAP_TSTAMP_PRECISION_NANO) != 0)
    throw core::Error(core::ErrorKind::io,
                      fmt::format("interface {}: libpcap cannot give nanosecond timestamps", options.interface));
  if (options.prefer_adapter) {
    int* types = nullptr;
    const int n = pcap_list_tstamp_types(handle, &types);
    bool adapter = false;
    for (int i = 0; i < n; ++i) adapter = adapter || types[i] == PCAP_TSTAMP_ADAPTER;
    if (n > 0) pcap_free_tstamp_types(types);
    // PCAP_TSTAMP_ADAPTER: the adapter's clock synchronised to the system's (CLOCK_REALTIME), the
    // only hardware kind comparable with the other board; an unsynchronised adapter clock is not.
    if (adapter && pcap_set_tstamp_type(handle, PCAP_TSTAMP_ADAPTER) == 0) capture.source_ = StampSource::adapter;
  }
  const int status = pcap_activate(handle);
  if (status < 0) {
    const auto kind = status == PCAP_ERROR_NO_SUCH_DEVICE ? core::ErrorKind::no_input : core::ErrorKind::io;
    throw core::Error(kind, fmt::format("interface {}: cannot capture: {}", options.interface, pcap_geterr(handle)));
  }
  if (status == PCAP_WARNING_TSTAMP_TYPE_NOTSUP) capture.source_ = StampSource::host;
  // In immediate mode libpcap's own read timeout does not apply on Linux (a read waits for the next
  // packet however long): reads do not block, and next() waits in poll() with its own timeout.
  if (pcap_setnonblock(handle, 1, error) != 0)
    throw core::Error(core::ErrorKind::io, fmt::format("interface {}: {}", options.interface, error));
  capture.link_type_ = pcap_datalink(handle);
  if (!is_supported_link_type(capture.link_type_))
    throw core::Error(core::ErrorKind::data, fmt::format("interface {}: link type {} is not one m2mlat decodes",
                                                         options.interface, link_type_text(capture.link_type_)));
  return capture;
}

void Capture::set_filter(const std::string& bpf) {
  auto program = std::make_shared<Filter>();
  if (pcap_compile(handle_, &program->program, bpf.c_str(), 1, PCAP_NETMASK_UNKNOWN) != 0)
    throw core::Error(core::ErrorKind::usage, fmt::format("filter '{}': {}", bpf, pcap_geterr(handle_)));
  program->compiled = true;
  if (live_) {
    // In the kernel: packets the filter refuses are never copied to this process.
    if (pcap_setfilter(handle_, &program->program) != 0)
      throw core::Error(core::ErrorKind::io, fmt::format("filter '{}': {}", bpf, pcap_geterr(handle_)));
  } else {
    filter_ = std::move(program);  // applied in next(), so that packet indexes stay the file's own
  }
}

void Capture::write_to(const std::string& path) {
  dumper_ = pcap_dump_open(handle_, path.c_str());
  if (dumper_ == nullptr)
    throw core::Error(core::ErrorKind::io, fmt::format("{}: cannot write: {}", path, pcap_geterr(handle_)));
}

bool Capture::next(RawPacket& packet) {
  for (;;) {
    pcap_pkthdr* header = nullptr;
    const u_char* data = nullptr;
    int status = pcap_next_ex(handle_, &header, &data);
    if (status == 0 && live_) {  // nothing yet: wait for the descriptor, at most the read timeout
      pollfd ready{pcap_get_selectable_fd(handle_), POLLIN, 0};
      if (::poll(&ready, 1, kLiveTimeoutMs) > 0) status = pcap_next_ex(handle_, &header, &data);
    }
    if (status == 0 || status == PCAP_ERROR_BREAK) return false;  // a live timeout; the end of a file
    if (status < 0) {
      throw core::Error(core::ErrorKind::data, fmt::format("{}: packet {}: cannot be read ({}); the {} before it were read",
                                                           name_, read_ + 1, pcap_geterr(handle_), read_));
    }
    ++read_;
    if (filter_ && pcap_offline_filter(&filter_->program, header, data) == 0) continue;
    if (dumper_ != nullptr) pcap_dump(reinterpret_cast<u_char*>(dumper_), header, data);
    // With nanosecond precision requested, libpcap's tv_usec field holds nanoseconds.
    packet.time_ns = seconds_since_epoch(header->ts.tv_sec) * 1'000'000'000 + std::int64_t{header->ts.tv_usec};
    packet.index = read_;
    packet.bytes = std::span<const std::uint8_t>(data, header->caplen);
    packet.wire_length = header->len;
    return true;
  }
}

std::uint64_t Capture::dropped() const {
  if (!live_) return 0;
  pcap_stat stats{};
  if (pcap_stats(handle_, &stats) != 0) return 0;
  return stats.ps_drop;
}

}  // namespace m2mlat::markers
