#include "io/image_guard.h"

#include <cctype>
#include <cstring>
#include <fstream>
#include <string>

namespace clothfit {
namespace {

constexpr unsigned char kExrMagic[4] = {0x76, 0x2f, 0x31, 0x01};
constexpr unsigned char kPngMagic[8] = {0x89, 'P',  'N',  'G',
                                        '\r', '\n', 0x1a, '\n'};
constexpr uint32_t kMultipartFlag = 0x1000;  // version field, bit 12
constexpr int kMaxNameLength = 255;          // with the long-names flag
constexpr int64_t kMaxLinesPerChunk = 256;   // DWAB compression

// Reads the file front to back, tracking what is left.
class HeaderReader {
 public:
  HeaderReader(std::ifstream& in, int64_t size) : in_(in), left_(size) {}

  int64_t left() const { return left_; }

  bool Bytes(void* out, int64_t n) {
    if (n > left_ || !in_.read(static_cast<char*>(out), n)) return false;
    left_ -= n;
    return true;
  }
  bool Skip(int64_t n) {
    if (n > left_ || !in_.seekg(n, std::ios::cur)) return false;
    left_ -= n;
    return true;
  }
  bool Int32(int32_t* value) {
    unsigned char b[4];
    if (!Bytes(b, 4)) return false;
    *value = static_cast<int32_t>(uint32_t{b[0]} | uint32_t{b[1]} << 8 |
                                  uint32_t{b[2]} << 16 | uint32_t{b[3]} << 24);
    return true;
  }
  // A null-terminated name of at most kMaxNameLength characters.
  bool Name(std::string* name) {
    name->clear();
    char c = 0;
    while (Bytes(&c, 1)) {
      if (c == '\0') return true;
      if (name->size() == kMaxNameLength) return false;
      name->push_back(c);
    }
    return false;
  }

 private:
  std::ifstream& in_;
  int64_t left_;
};

// One header: attributes until an empty name. `*empty`: the header had no
// attribute (the end of a multi-part file's header list).
std::string CheckHeader(HeaderReader& reader, int64_t file_size,
                        int64_t max_pixels, bool* empty) {
  const std::string truncated = "truncated OpenEXR header";
  *empty = true;
  std::string name, type;
  while (true) {
    if (!reader.Name(&name)) return truncated;
    if (name.empty()) return "";
    *empty = false;
    int32_t size = 0;
    if (!reader.Name(&type) || !reader.Int32(&size)) return truncated;
    if (size < 0 || size > reader.left()) {
      return "OpenEXR attribute '" + name + "' claims " + std::to_string(size) +
             " bytes, the file has " + std::to_string(reader.left()) + " left";
    }
    if ((name == "dataWindow" || name == "displayWindow") && type == "box2i" &&
        size == 16) {
      int32_t box[4] = {0, 0, 0, 0};
      for (int32_t& v : box) {
        if (!reader.Int32(&v)) return truncated;
      }
      const int64_t width = int64_t{box[2]} - box[0] + 1;
      const int64_t height = int64_t{box[3]} - box[1] + 1;
      if (name == "dataWindow" &&
          (width < 1 || height < 1 || width > max_pixels / height)) {
        return "OpenEXR data window of " + std::to_string(width) + " x " +
               std::to_string(height) + " pixels (at most " +
               std::to_string(max_pixels) + ")";
      }
      // The line-offset table holds 8 bytes per chunk of at most 256 lines
      // (DWAB; 1-32 for the other compressions): a short file cannot hold
      // many lines, however tall its data window says it is.
      if (name == "dataWindow" && height / kMaxLinesPerChunk * 8 > file_size) {
        return "OpenEXR data window of " + std::to_string(height) +
               " lines in a file of " + std::to_string(file_size) + " bytes";
      }
    } else if (!reader.Skip(size)) {
      return truncated;
    }
  }
}

// After the magic number: the version field, then the headers.
std::string CheckExr(HeaderReader& reader, int64_t file_size,
                     int64_t max_pixels) {
  int32_t version = 0;
  if (!reader.Int32(&version)) return "truncated OpenEXR header";
  const bool multipart = (static_cast<uint32_t>(version) & kMultipartFlag) != 0;
  bool empty = false;
  do {
    const std::string problem =
        CheckHeader(reader, file_size, max_pixels, &empty);
    if (!problem.empty()) return problem;
  } while (multipart && !empty);
  return "";
}

// After the 8-byte signature: chunks up to IEND.
std::string CheckPng(HeaderReader& reader) {
  while (true) {
    unsigned char head[8];
    if (!reader.Bytes(head, 8)) return "truncated PNG: no IEND chunk";
    const uint32_t length = uint32_t{head[0]} << 24 | uint32_t{head[1]} << 16 |
                            uint32_t{head[2]} << 8 | uint32_t{head[3]};
    std::string type(reinterpret_cast<const char*>(head + 4), 4);
    for (char& c : type) {
      if (!std::isalpha(static_cast<unsigned char>(c))) c = '?';
    }
    if (int64_t{length} + 4 > reader.left()) {
      return "truncated PNG: chunk '" + type + "' needs " +
             std::to_string(int64_t{length} + 4) + " bytes, the file has " +
             std::to_string(reader.left()) + " left";
    }
    if (type == "IEND") return "";
    reader.Skip(int64_t{length} + 4);  // data and CRC
  }
}

}  // namespace

std::string CheckImageHeader(const std::string& path, int64_t max_pixels) {
  std::ifstream in(path, std::ios::binary);
  if (!in || !in.seekg(0, std::ios::end)) return "";  // left to the reader
  const int64_t size = in.tellg();
  in.seekg(0);
  HeaderReader reader(in, size);
  unsigned char magic[8];
  if (!reader.Bytes(magic, 4)) return "";
  if (std::memcmp(magic, kExrMagic, 4) == 0) {
    return CheckExr(reader, size, max_pixels);
  }
  if (std::memcmp(magic, kPngMagic, 4) == 0 && reader.Bytes(magic + 4, 4) &&
      std::memcmp(magic, kPngMagic, 8) == 0) {
    return CheckPng(reader);
  }
  return "";
}

}  // namespace clothfit
