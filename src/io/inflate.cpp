#include "io/inflate.hpp"

#include <zlib.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "io/parse_errors.hpp"
#include "tpmsfill/error.hpp"

namespace tpmsfill::detail {

std::string inflate_bytes(std::string_view data, const std::string& source, std::uint64_t max_bytes,
                          const DeclaredSize& declared) {
  z_stream z{};
  if (inflateInit2(&z, 15 + 32) != Z_OK) throw Error(source + ": cannot start zlib");
  const std::unique_ptr<z_stream, int (*)(z_stream*)> guard(&z, inflateEnd);
  std::string out;
  // A single gzip member's last four bytes hold its size modulo 2^32: room for that much
  // spares the string's doublings, which held twice the data at the end. Deflate expands at
  // most 1032 times, so a larger claim is a lie.
  std::uint64_t claimed = 0;
  if (data.size() >= 18 && static_cast<unsigned char>(data[0]) == 0x1f &&
      static_cast<unsigned char>(data[1]) == 0x8b) {
    const auto* tail = reinterpret_cast<const unsigned char*>(data.data() + data.size() - 4);
    claimed = std::min(tail[0] | tail[1] << 8 | tail[2] << 16 | std::uint64_t{tail[3]} << 24,
                       1032 * static_cast<std::uint64_t>(data.size()));
  }
  std::uint64_t limit = max_bytes;
  bool declared_limit = false;
  // The limit settled (by the declared size, once its head is in), then the room reserved
  // within it: a gzip of zeros under a header declaring 84 bytes reserves no gigabyte.
  const auto settle = [&](std::string_view head) {
    if (declared.total)
      if (const std::uint64_t total = declared.total(head); total > 0 && total < limit) {
        limit = total;
        declared_limit = true;
      }
    if (out.size() < claimed) out.reserve(static_cast<std::size_t>(std::min(claimed, limit + 1)));
  };
  bool head_read = !declared.total || declared.head == 0;
  if (head_read) settle({});
  std::vector<unsigned char> chunk(std::size_t{1} << 18);
  std::uint64_t consumed = 0;  // input handed to zlib so far
  auto feed = [&] {
    const std::uint64_t n = std::min<std::uint64_t>(data.size() - consumed, 1u << 30);
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data() + consumed));
    z.avail_in = static_cast<uInt>(n);
    consumed += n;
  };
  feed();
  while (true) {
    z.next_out = chunk.data();
    z.avail_out = static_cast<uInt>(chunk.size());
    const int rc = inflate(&z, Z_NO_FLUSH);
    const std::uint64_t offset = consumed - z.avail_in;
    if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR)
      fail_at_byte(source, offset,
                   std::string("corrupt compressed data: ") + (z.msg ? z.msg : "zlib error"));
    out.append(reinterpret_cast<const char*>(chunk.data()), chunk.size() - z.avail_out);
    if (!head_read && out.size() >= declared.head) {
      head_read = true;
      settle(out);
    }
    if (out.size() > limit)
      throw InputError(
          source + " decompresses to more than " + std::to_string(limit) +
          (declared_limit ? " bytes, the size its header declares" : " bytes (the limit)"));
    if (z.avail_in == 0 && consumed < data.size()) feed();
    if (rc == Z_STREAM_END) {
      // Concatenated gzip members form one stream (gzip(1) and zlib's gzopen agree).
      if (z.avail_in >= 2 && z.next_in[0] == 0x1f && z.next_in[1] == 0x8b) {
        inflateReset(&z);
        continue;
      }
      break;
    }
    if (rc == Z_BUF_ERROR && z.avail_in == 0 && consumed == data.size())
      fail_at_byte(source, data.size(), "compressed data is truncated");
  }
  return out;
}

}  // namespace tpmsfill::detail
