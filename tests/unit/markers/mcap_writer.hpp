// A small MCAP writer for the tests, written from the specification (https://mcap.dev/spec), byte by
// byte: the bags the reader's tests read are made here, so no recorder or library is needed.
#pragma once

#include <lz4frame.h>
#include <zstd.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace m2mlat::markers::mcap_test {

inline constexpr std::string_view kWriterMagic{"\x89MCAP0\r\n", 8};

inline void put_le(std::string& out, std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out += static_cast<char>((value >> (8 * i)) & 0xFFU);
}
inline void put_text(std::string& out, std::string_view text) {
  put_le(out, text.size(), 4);
  out += text;
}
inline std::string record(std::uint8_t op, const std::string& content) {
  std::string out(1, static_cast<char>(op));
  put_le(out, content.size(), 8);
  return out + content;
}

inline std::string header_record(std::string_view profile = "ros2") {
  std::string c;
  put_text(c, profile);
  put_text(c, "m2mlat test writer");
  return record(0x01, c);
}
inline std::string schema_record(std::uint16_t id, std::string_view name, std::string_view definition) {
  std::string c;
  put_le(c, id, 2);
  put_text(c, name);
  put_text(c, "ros2msg");
  put_text(c, definition);
  return record(0x03, c);
}
inline std::string channel_record(std::uint16_t id, std::uint16_t schema, std::string_view topic) {
  std::string c;
  put_le(c, id, 2);
  put_le(c, schema, 2);
  put_text(c, topic);
  put_text(c, "cdr");
  put_le(c, 0, 4);  // metadata: an empty map
  return record(0x04, c);
}
inline std::string message_record(std::uint16_t channel, std::uint32_t sequence, std::uint64_t log_time,
                                  const std::string& data) {
  std::string c;
  put_le(c, channel, 2);
  put_le(c, sequence, 4);
  put_le(c, log_time, 8);
  put_le(c, log_time, 8);  // publish_time
  return record(0x05, c + data);
}

// A CDR message beginning with std_msgs/Header: stamp (sec, nanosec), frame_id, then `tail` bytes.
inline std::string stamped_cdr(std::int32_t sec, std::uint32_t nanosec, bool little = true) {
  std::string out{'\0', static_cast<char>(little ? 1 : 0), '\0', '\0'};
  const auto put = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) {
      const int shift = little ? 8 * i : 8 * (3 - i);
      out += static_cast<char>((v >> shift) & 0xFFU);
    }
  };
  put(static_cast<std::uint32_t>(sec));
  put(nanosec);
  put(5);  // frame_id: "base" and its NUL
  out += std::string("base\0", 5);
  out += std::string(3, '\0');  // alignment for what follows
  out += std::string(16, '\x11');  // the rest of the message (a Twist's first values, say)
  return out;
}

// A chunk of `records` compressed with "", "zstd" or "lz4"; `crc` is written as given (0: none).
inline std::string chunk_record(const std::string& records, std::string_view compression, std::uint32_t crc = 0) {
  std::string body;
  if (compression.empty()) {
    body = records;
  } else if (compression == "zstd") {
    body.resize(ZSTD_compressBound(records.size()));
    const auto n = ZSTD_compress(body.data(), body.size(), records.data(), records.size(), 3);
    if (ZSTD_isError(n) != 0) throw std::runtime_error("zstd");
    body.resize(n);
  } else if (compression == "lz4") {
    body.resize(LZ4F_compressFrameBound(records.size(), nullptr));
    const auto n = LZ4F_compressFrame(body.data(), body.size(), records.data(), records.size(), nullptr);
    if (LZ4F_isError(n) != 0) throw std::runtime_error("lz4");
    body.resize(n);
  } else {
    body = records;  // an unknown compression: the bytes as they are
  }
  std::string c;
  put_le(c, 0, 8);  // message_start_time
  put_le(c, 0, 8);  // message_end_time
  put_le(c, records.size(), 8);
  put_le(c, crc, 4);
  put_text(c, compression);
  put_le(c, body.size(), 8);
  return record(0x06, c + body);
}

inline std::string data_end_record() {
  std::string c;
  put_le(c, 0, 4);
  return record(0x0F, c);
}
inline std::string footer_record() {
  std::string c;
  put_le(c, 0, 8);
  put_le(c, 0, 8);
  put_le(c, 0, 4);
  return record(0x02, c);
}

// A whole file: magic, header, the data records, Data End, a summary (a repeated channel), footer, magic.
inline std::string mcap_file(const std::string& data_records, const std::string& summary = {}) {
  return std::string(kWriterMagic) + header_record() + data_records + data_end_record() + summary + footer_record() +
         std::string(kWriterMagic);
}

}  // namespace m2mlat::markers::mcap_test
