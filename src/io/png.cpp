#include "io/png.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <vector>

#include "core/parallel.hpp"

namespace tpmsfill::detail {
namespace {

// PNG stores every integer big-endian.
void put_u32(std::string& s, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) s.push_back(static_cast<char>((v >> shift) & 0xff));
}

// The CRC covers the type and the data, not the length.
void put_chunk(std::string& png, const char* type, const std::string& data) {
  put_u32(png, static_cast<std::uint32_t>(data.size()));
  const std::string body = std::string(type, 4) + data;
  png += body;
  put_u32(png, static_cast<std::uint32_t>(
                   crc32(0, reinterpret_cast<const Bytef*>(body.data()), body.size())));
}

// One row through one filter into `out`; returns the sum of |signed bytes|, the heuristic the
// PNG specification recommends for choosing a row's filter. The filter is a template argument
// so each loop is branch-free and vectorises.
template <int kFilter>
long filter_row(const std::uint8_t* row, const std::uint8_t* prev, std::size_t stride,
                std::size_t bpp, std::uint8_t* out) {
  long cost = 0;
  for (std::size_t i = 0; i < stride; ++i) {
    const int a = i >= bpp ? row[i - bpp] : 0, b = prev[i], c = i >= bpp ? prev[i - bpp] : 0;
    int predictor = 0;
    if constexpr (kFilter == 1) predictor = a;
    if constexpr (kFilter == 2) predictor = b;
    if constexpr (kFilter == 3) predictor = (a + b) / 2;
    if constexpr (kFilter == 4) {
      const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
      predictor = pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
    }
    out[i] = static_cast<std::uint8_t>(row[i] - predictor);
    cost += std::abs(static_cast<int>(static_cast<std::int8_t>(out[i])));
  }
  return cost;
}

// The filtered scanlines (a filter-type byte, then the row), the bytes IDAT compresses. A row's
// choice depends only on the source pixels, so rows are filtered in parallel, each into its
// own slot: the bytes do not depend on the thread count.
std::vector<std::uint8_t> filter_rows(int width, int height, int channels,
                                      const std::uint8_t* pixels) {
  const std::size_t stride = static_cast<std::size_t>(width) * channels;
  const std::size_t bpp = static_cast<std::size_t>(channels);  // left neighbour, in bytes
  std::vector<std::uint8_t> raw((stride + 1) * height), zero(stride, 0);
  parallel_for(static_cast<std::size_t>(height), 32, [&](std::size_t begin, std::size_t end) {
    std::vector<std::uint8_t> trial(stride);
    for (std::size_t y = begin; y < end; ++y) {
      const std::uint8_t* row = pixels + y * stride;
      const std::uint8_t* prev = y > 0 ? pixels + (y - 1) * stride : zero.data();
      std::uint8_t* out = &raw[y * (stride + 1)];
      long best = filter_row<0>(row, prev, stride, bpp, out + 1);
      out[0] = 0;
      const auto consider = [&](int filter, long cost) {
        if (cost >= best) return;
        best = cost;
        out[0] = static_cast<std::uint8_t>(filter);
        std::copy(trial.begin(), trial.end(), out + 1);
      };
      consider(1, filter_row<1>(row, prev, stride, bpp, trial.data()));
      consider(2, filter_row<2>(row, prev, stride, bpp, trial.data()));
      consider(3, filter_row<3>(row, prev, stride, bpp, trial.data()));
      consider(4, filter_row<4>(row, prev, stride, bpp, trial.data()));
    }
  });
  return raw;
}

}  // namespace

std::string encode_png(int width, int height, int channels, const std::uint8_t* pixels,
                       std::uint32_t pixels_per_metre) {
  // The format's limit on a side is 2^31 - 1; the row filters index rows in size_t.
  if (width <= 0 || height <= 0) throw std::invalid_argument("encode_png: empty image");
  if (channels != 1 && channels != 3) throw std::invalid_argument("encode_png: 1 or 3 channels");
  const std::vector<std::uint8_t> raw = filter_rows(width, height, channels, pixels);
  uLongf packed_size = compressBound(raw.size());
  std::string packed(packed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size, raw.data(), raw.size(),
                Z_BEST_COMPRESSION) != Z_OK)
    throw std::runtime_error("zlib could not compress the image");
  packed.resize(packed_size);

  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::string header;
  put_u32(header, static_cast<std::uint32_t>(width));
  put_u32(header, static_cast<std::uint32_t>(height));
  header.push_back(8);                       // bits per sample
  header.push_back(channels == 1 ? 0 : 2);   // colour type: greyscale or RGB
  header += std::string("\x00\x00\x00", 3);  // deflate, adaptive filters, no interlace
  put_chunk(png, "IHDR", header);
  if (pixels_per_metre > 0) {
    std::string phys;
    put_u32(phys, pixels_per_metre);
    put_u32(phys, pixels_per_metre);
    phys.push_back(1);  // the unit is the metre
    put_chunk(png, "pHYs", phys);
  }
  put_chunk(png, "IDAT", packed);
  put_chunk(png, "IEND", "");
  return png;
}

}  // namespace tpmsfill::detail
