// The MCAP records, read from a mapped file (mcap_reader.hpp). Little-endian integers read byte by
// byte, so the reader is the same on every host.
#include "m2mlat/markers/mcap_reader.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <lz4frame.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <zstd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <memory>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fd.hpp"
#include "m2mlat/core/printable.hpp"

namespace m2mlat::markers {

namespace {

constexpr std::array<std::uint8_t, 8> kMcapMagic{0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

enum McapOp : std::uint8_t {
  kOpHeader = 0x01,
  kOpFooter = 0x02,
  kOpSchema = 0x03,
  kOpChannel = 0x04,
  kOpMessage = 0x05,
  kOpChunk = 0x06,
  kOpDataEnd = 0x0F,
};

// A file mapped read-only; unmapped at the end.
class McapMappedFile {
 public:
  explicit McapMappedFile(const std::string& path) {
    core::Fd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    if (!fd)
      throw core::Error(errno == ENOENT ? core::ErrorKind::no_input : core::ErrorKind::io,
                        fmt::format("{}: {}", path, std::strerror(errno)));
    struct stat st {};
    if (::fstat(fd.get(), &st) != 0)
      throw core::Error(core::ErrorKind::io, fmt::format("{}: {}", path, std::strerror(errno)));
    if (!S_ISREG(st.st_mode)) throw core::Error(core::ErrorKind::data, fmt::format("{}: not a regular file", path));
    size_ = static_cast<std::size_t>(st.st_size);
    if (size_ == 0) return;
    void* at = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd.get(), 0);
    if (at == MAP_FAILED) throw core::Error(core::ErrorKind::io, fmt::format("{}: mmap: {}", path, std::strerror(errno)));
    data_ = static_cast<const std::uint8_t*>(at);
  }
  McapMappedFile(const McapMappedFile&) = delete;
  McapMappedFile& operator=(const McapMappedFile&) = delete;
  ~McapMappedFile() {
    if (data_ != nullptr) ::munmap(const_cast<std::uint8_t*>(data_), size_);
  }
  const std::uint8_t* data() const { return data_; }
  std::size_t size() const { return size_; }

 private:
  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
};

// CRC-32 (IEEE 802.3, reflected, the one MCAP names), table made once.
std::uint32_t mcap_crc32(const std::uint8_t* data, std::size_t size) {
  static const auto table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t crc = 0xFFFFFFFFU;
  for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ data[i]) & 0xFFU] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFU;
}

// Reads the fields of one record's content; every read checks the bounds and names the record.
class McapFields {
 public:
  McapFields(const std::uint8_t* data, std::size_t size, std::string where)
      : data_(data), size_(size), where_(std::move(where)) {}

  std::uint64_t uint(int bytes, std::string_view field) {
    need(static_cast<std::size_t>(bytes), field);
    std::uint64_t v = 0;
    for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | data_[pos_ + static_cast<std::size_t>(i)];
    pos_ += static_cast<std::size_t>(bytes);
    return v;
  }
  std::string_view bytes(std::size_t n, std::string_view field) {
    need(n, field);
    std::string_view out(reinterpret_cast<const char*>(data_ + pos_), n);
    pos_ += n;
    return out;
  }
  std::string text(std::string_view field) { return std::string(bytes(uint(4, field), field)); }
  std::string_view rest() { return bytes(size_ - pos_, "data"); }
  [[noreturn]] void fail(std::string_view what) const {
    throw core::Error(core::ErrorKind::data, fmt::format("{}: {}", where_, what));
  }

 private:
  void need(std::size_t n, std::string_view field) {
    if (n > size_ - pos_)
      fail(fmt::format("field '{}' needs {} bytes, the record has {} left: damaged", field, n, size_ - pos_));
  }
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  std::string where_;
};

std::string mcap_decompress(std::string_view compression, const std::uint8_t* data, std::size_t size,
                       std::uint64_t uncompressed_size, const std::string& where) {
  // A chunk's uncompressed size is written in it; refuse an absurd one before allocating it.
  constexpr std::uint64_t kMaxChunk = std::uint64_t{1} << 32;
  if (uncompressed_size > kMaxChunk)
    throw core::Error(core::ErrorKind::data, fmt::format("{}: chunk of {} bytes uncompressed: damaged", where,
                                                         uncompressed_size));
  std::string out(static_cast<std::size_t>(uncompressed_size), '\0');
  if (compression.empty()) {
    if (size != uncompressed_size)
      throw core::Error(core::ErrorKind::data, fmt::format("{}: uncompressed chunk of {} bytes says {}: damaged",
                                                           where, size, uncompressed_size));
    if (size != 0) std::memcpy(out.data(), data, size);
    return out;
  }
  if (compression == "zstd") {
    const std::size_t got = ZSTD_decompress(out.data(), out.size(), data, size);
    if (ZSTD_isError(got) != 0 || got != uncompressed_size)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}: zstd chunk does not decompress to its {} bytes: {}", where,
                                    uncompressed_size,
                                    ZSTD_isError(got) != 0 ? ZSTD_getErrorName(got) : "size differs"));
    return out;
  }
  if (compression == "lz4") {
    LZ4F_dctx* raw = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION)) != 0)
      throw core::Error(core::ErrorKind::internal, "lz4: no decompression context");
    std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> context(raw, &LZ4F_freeDecompressionContext);
    std::size_t in_at = 0, out_at = 0;
    for (;;) {
      std::size_t out_size = out.size() - out_at;
      std::size_t in_size = size - in_at;
      const std::size_t hint =
          LZ4F_decompress(context.get(), out.data() + out_at, &out_size, data + in_at, &in_size, nullptr);
      if (LZ4F_isError(hint) != 0)
        throw core::Error(core::ErrorKind::data,
                          fmt::format("{}: lz4 chunk: {}", where, LZ4F_getErrorName(hint)));
      in_at += in_size;
      out_at += out_size;
      if (hint == 0) break;  // the frame is complete
      if (in_size == 0 && out_size == 0)
        throw core::Error(core::ErrorKind::data, fmt::format("{}: lz4 chunk ends inside its frame: damaged", where));
    }
    if (out_at != uncompressed_size)
      throw core::Error(core::ErrorKind::data, fmt::format("{}: lz4 chunk gives {} bytes, it says {}: damaged",
                                                           where, out_at, uncompressed_size));
    return out;
  }
  throw core::Error(core::ErrorKind::data,
                    fmt::format("{}: chunk compression '{}' is not supported (none, zstd and lz4 are)", where,
                                core::printable(compression)));
}

// A record's head: its opcode and the length of its content, which follows the 9 bytes of head.
struct McapRecordHead {
  std::uint8_t op = 0;
  std::size_t length = 0;
};

// The head of the record at byte `at` of `size` bytes (the file's, or a chunk's records when
// `in_chunk`), checked to lie inside them with its content; `where` names the record in the errors.
McapRecordHead mcap_record_head(const std::uint8_t* data, std::size_t size, std::size_t at, const std::string& where,
                                bool in_chunk) {
  if (size - at < 9) {
    if (in_chunk)
      throw core::Error(core::ErrorKind::data, fmt::format("{}: a record's opcode and length cut short: damaged", where));
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: truncated: the file ends {} (no Footer record): a recording that was cut short",
                                  where, at == size ? "there" : "inside a record's opcode and length"));
  }
  const std::uint8_t op = data[at];
  std::uint64_t length = 0;  // little-endian
  for (int i = 8; i >= 1; --i) length = (length << 8) | data[at + static_cast<std::size_t>(i)];
  if (length > size - at - 9) {
    if (in_chunk)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}: record (opcode {:#04x}) of {} bytes runs past the chunk's end: damaged", where,
                                    op, length));
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: truncated: record (opcode {:#04x}) of {} bytes runs past the end of the file "
                                  "({} bytes)",
                                  where, op, length, size));
  }
  return {op, static_cast<std::size_t>(length)};
}

class McapParse {
 public:
  McapParse(const std::string& path, const McapOnMessage& on_message) : path_(path), on_message_(on_message) {}

  McapSummary run(const std::uint8_t* data, std::size_t size) {
    if (size < kMcapMagic.size() || std::memcmp(data, kMcapMagic.data(), kMcapMagic.size()) != 0)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}: not an MCAP file (no MCAP magic at offset 0)", path_));
    std::size_t at = kMcapMagic.size();
    bool data_end = false;
    for (;;) {
      const std::string where = fmt::format("{}: offset {}", path_, at);
      const auto [op, n] = mcap_record_head(data, size, at, where, false);
      const std::size_t content = at + 9;
      if (op == kOpFooter) {
        const std::size_t end = content + n;
        if (size - end != kMcapMagic.size() || std::memcmp(data + end, kMcapMagic.data(), kMcapMagic.size()) != 0)
          throw core::Error(core::ErrorKind::data,
                            fmt::format("{}: offset {}: the Footer is not followed by the closing MCAP magic and "
                                        "the end of the file: damaged",
                                        path_, end));
        return std::move(summary_);
      }
      if (op == kOpDataEnd) data_end = true;
      // After Data End comes the summary section: it repeats schemas and channels; skipped.
      if (!data_end) record(op, data + content, n, where, at, nullptr);
      at = content + n;
    }
  }

 private:
  // One record of the data section (or of a chunk: `chunk_at` is then the chunk's file offset).
  void record(std::uint8_t op, const std::uint8_t* data, std::size_t size, const std::string& where,
              std::size_t offset, const std::size_t* chunk_at) {
    McapFields f(data, size, where);
    switch (op) {
      case kOpHeader: summary_.profile = f.text("profile"); break;
      case kOpSchema: {
        McapSchema s;
        s.id = static_cast<std::uint16_t>(f.uint(2, "id"));
        s.name = f.text("name");
        s.encoding = f.text("encoding");
        s.data = std::string(f.bytes(f.uint(4, "data length"), "data"));
        if (s.id == 0) f.fail("schema id 0 is reserved: damaged");
        summary_.schemas[s.id] = std::move(s);
        break;
      }
      case kOpChannel: {
        McapChannel c;
        c.id = static_cast<std::uint16_t>(f.uint(2, "id"));
        c.schema_id = static_cast<std::uint16_t>(f.uint(2, "schema_id"));
        c.topic = f.text("topic");
        c.message_encoding = f.text("message_encoding");
        if (c.schema_id != 0 && !summary_.schemas.contains(c.schema_id))
          f.fail(fmt::format("channel {} ('{}') names schema {}, which no Schema record before it defines", c.id,
                             core::printable(c.topic), c.schema_id));
        if (const auto it = summary_.channels.find(c.id); it != summary_.channels.end() && it->second.topic != c.topic)
          f.fail(fmt::format("channel {} is '{}' here and '{}' before: damaged", c.id, core::printable(c.topic),
                             core::printable(it->second.topic)));
        summary_.channels[c.id] = std::move(c);
        break;
      }
      case kOpMessage: {
        McapMessage m;
        m.channel_id = static_cast<std::uint16_t>(f.uint(2, "channel_id"));
        m.sequence = static_cast<std::uint32_t>(f.uint(4, "sequence"));
        m.log_time = f.uint(8, "log_time");
        m.publish_time = f.uint(8, "publish_time");
        m.data = f.rest();
        const auto channel = summary_.channels.find(m.channel_id);
        if (channel == summary_.channels.end())
          f.fail(fmt::format("message names channel {}, which no Channel record before it defines", m.channel_id));
        m.where = chunk_at != nullptr ? fmt::format("chunk at offset {}, byte {}", *chunk_at, offset)
                                      : fmt::format("offset {}", offset);
        ++summary_.messages[m.channel_id];
        const auto schema = summary_.schemas.find(channel->second.schema_id);
        on_message_(channel->second, schema == summary_.schemas.end() ? nullptr : &schema->second, m);
        break;
      }
      case kOpChunk: {
        if (chunk_at != nullptr) f.fail("a chunk inside a chunk: damaged");
        f.uint(8, "message_start_time");
        f.uint(8, "message_end_time");
        const std::uint64_t uncompressed_size = f.uint(8, "uncompressed_size");
        const auto crc = static_cast<std::uint32_t>(f.uint(4, "uncompressed_crc"));
        const std::string compression = f.text("compression");
        const std::string_view records = f.bytes(f.uint(8, "records length"), "records");
        const std::string plain = mcap_decompress(compression, reinterpret_cast<const std::uint8_t*>(records.data()),
                                             records.size(), uncompressed_size, where);
        const auto* bytes = reinterpret_cast<const std::uint8_t*>(plain.data());
        if (crc != 0 && mcap_crc32(bytes, plain.size()) != crc)
          f.fail(fmt::format("chunk's CRC-32 is {:#010x}, its records give {:#010x}: damaged", crc,
                             mcap_crc32(bytes, plain.size())));
        ++summary_.chunks;
        std::size_t at = 0;
        while (at < plain.size()) {
          const std::string inner = fmt::format("{}: chunk at offset {}, byte {}", path_, offset, at);
          const auto [inner_op, length] = mcap_record_head(bytes, plain.size(), at, inner, true);
          record(inner_op, bytes + at + 9, length, inner, at, &offset);
          at += 9 + length;
        }
        break;
      }
      default: break;  // indexes, attachments, metadata, statistics: not needed for markers
    }
  }

  const std::string& path_;
  const McapOnMessage& on_message_;
  McapSummary summary_;
};

}  // namespace

McapSummary read_mcap(const std::string& path, const McapOnMessage& on_message) {
  const McapMappedFile file(path);
  McapParse parse(path, on_message);
  return parse.run(file.data(), file.size());
}

}  // namespace m2mlat::markers
