#include "export/png.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace clothfit {
namespace {

uint32_t Crc32(const std::string& bytes, size_t begin) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t n = 0; n < 256; ++n) {
      uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  uint32_t c = 0xFFFFFFFFu;
  for (size_t i = begin; i < bytes.size(); ++i) {
    c = table[(c ^ static_cast<uint8_t>(bytes[i])) & 0xFF] ^ (c >> 8);
  }
  return c ^ 0xFFFFFFFFu;
}

void Be32(uint32_t v, std::string* out) {
  for (int k = 3; k >= 0; --k) out->push_back(static_cast<char>(v >> (8 * k)));
}

void Chunk(const char* type, const std::string& data, std::string* out) {
  Be32(static_cast<uint32_t>(data.size()), out);
  const size_t start = out->size();
  out->append(type, 4);
  out->append(data);
  Be32(Crc32(*out, start), out);
}

}  // namespace

std::string EncodePng(int width, int height, int channels,
                      const std::vector<uint8_t>& pixels) {
  if (width < 1 || height < 1 || (channels != 3 && channels != 4) ||
      pixels.size() != size_t(width) * height * channels) {
    throw std::invalid_argument("EncodePng: size does not match the pixels");
  }
  // The scanlines, each after its filter byte 0.
  std::string raw;
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);
    raw.append(reinterpret_cast<const char*>(pixels.data()) +
                   size_t(y) * width * channels,
               size_t(width) * channels);
  }
  // zlib (RFC 1950) of stored deflate blocks (RFC 1951 §3.2.4).
  std::string z = {0x78, 0x01};
  for (size_t at = 0; at < raw.size() || at == 0; at += 65535) {
    const size_t n = std::min<size_t>(65535, raw.size() - at);
    const bool last = at + n >= raw.size();
    z.push_back(last ? 1 : 0);
    z.push_back(static_cast<char>(n & 0xFF));
    z.push_back(static_cast<char>(n >> 8));
    z.push_back(static_cast<char>(~n & 0xFF));
    z.push_back(static_cast<char>((~n >> 8) & 0xFF));
    z.append(raw, at, n);
    if (last) break;
  }
  uint32_t a = 1, b = 0;  // Adler-32
  for (unsigned char c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  Be32((b << 16) | a, &z);
  std::string png = "\x89PNG\r\n\x1a\n";
  std::string header;
  Be32(static_cast<uint32_t>(width), &header);
  Be32(static_cast<uint32_t>(height), &header);
  header += {8, static_cast<char>(channels == 4 ? 6 : 2), 0, 0, 0};
  Chunk("IHDR", header, &png);
  Chunk("IDAT", z, &png);
  Chunk("IEND", "", &png);
  return png;
}

uint8_t LinearByte(double value) {
  const double v = std::clamp(value, 0.0, 1.0);
  return static_cast<uint8_t>(std::lround(v * 255.0));
}

uint8_t SrgbByte(double linear) {
  const double v = std::clamp(linear, 0.0, 1.0);
  const double s =
      v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
  return LinearByte(s);
}

double SrgbToLinear(uint8_t byte) {
  const double s = byte / 255.0;
  return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}

}  // namespace clothfit
