// SPDX-License-Identifier: GPL-3.0-or-later
// A minimal PNG writer (8-bit RGB, stored deflate blocks, no compression library needed) for the CLI's
// checkerboard texture.
#ifndef CROSSPARAM_CLI_PNG_H
#define CROSSPARAM_CLI_PNG_H

#include <array>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace crossparam {
namespace cli {

inline std::uint32_t crc32(const unsigned char* data, std::size_t n, std::uint32_t crc = 0xffffffffu) {
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= data[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return crc;
}

/// Writes an RGB image (row-major, width * height pixels) as PNG.
inline void write_png(std::ostream& os, int width, int height, const std::vector<std::array<unsigned char, 3>>& rgb) {
  auto be32 = [](std::vector<unsigned char>& v, std::uint32_t x) {
    for (int s = 24; s >= 0; s -= 8) v.push_back(static_cast<unsigned char>(x >> s));
  };
  auto chunk = [&](const char* type, const std::vector<unsigned char>& data) {
    std::vector<unsigned char> c(type, type + 4);
    c.insert(c.end(), data.begin(), data.end());
    std::vector<unsigned char> len;
    be32(len, std::uint32_t(data.size()));
    os.write(reinterpret_cast<const char*>(len.data()), 4);
    os.write(reinterpret_cast<const char*>(c.data()), std::streamsize(c.size()));
    std::vector<unsigned char> crc;
    be32(crc, crc32(c.data(), c.size()) ^ 0xffffffffu);
    os.write(reinterpret_cast<const char*>(crc.data()), 4);
  };
  static const unsigned char sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
  os.write(reinterpret_cast<const char*>(sig), 8);
  std::vector<unsigned char> ihdr;
  be32(ihdr, std::uint32_t(width));
  be32(ihdr, std::uint32_t(height));
  ihdr.insert(ihdr.end(), {8, 2, 0, 0, 0}); // 8 bit, RGB
  chunk("IHDR", ihdr);
  std::vector<unsigned char> raw;
  for (int y = 0; y < height; ++y) {
    raw.push_back(0); // filter: none
    for (int x = 0; x < width; ++x) {
      const auto& p = rgb[std::size_t(y) * width + x];
      raw.insert(raw.end(), p.begin(), p.end());
    }
  }
  // zlib stream of stored blocks.
  std::vector<unsigned char> z{0x78, 0x01};
  std::uint32_t a = 1, b = 0;
  for (unsigned char c : raw) {
    a = (a + c) % 65521u;
    b = (b + a) % 65521u;
  }
  for (std::size_t pos = 0; pos < raw.size() || pos == 0;) {
    std::size_t n = std::min<std::size_t>(65535, raw.size() - pos);
    const bool last = pos + n >= raw.size();
    z.push_back(last ? 1 : 0);
    z.push_back(static_cast<unsigned char>(n & 0xff));
    z.push_back(static_cast<unsigned char>(n >> 8));
    z.push_back(static_cast<unsigned char>(~n & 0xff));
    z.push_back(static_cast<unsigned char>((~n >> 8) & 0xff));
    z.insert(z.end(), raw.begin() + std::ptrdiff_t(pos), raw.begin() + std::ptrdiff_t(pos + n));
    pos += n;
    if (last) break;
  }
  be32(z, (b << 16) | a);
  chunk("IDAT", z);
  chunk("IEND", {});
}

} // namespace cli
} // namespace crossparam

#endif // CROSSPARAM_CLI_PNG_H
