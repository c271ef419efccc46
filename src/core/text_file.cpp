#include "trueaxis/core/text_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <unistd.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis {

namespace {

void AppendUtf8(std::string& out, std::uint32_t cp) {
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

std::string Utf16ToUtf8(std::string_view bytes, bool little_endian, const std::string& path) {
  std::string out;
  out.reserve(bytes.size() / 2);
  auto unit = [&](std::size_t i) -> std::uint32_t {
    const auto a = static_cast<unsigned char>(bytes[i]), b = static_cast<unsigned char>(bytes[i + 1]);
    return little_endian ? (a | (b << 8)) : ((a << 8) | b);
  };
  for (std::size_t i = 0; i + 1 < bytes.size(); i += 2) {
    std::uint32_t cp = unit(i);
    if (cp >= 0xD800 && cp <= 0xDBFF && i + 3 < bytes.size()) {
      const std::uint32_t lo = unit(i + 2);
      if (lo >= 0xDC00 && lo <= 0xDFFF) {
        cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
        i += 2;
      }
    }
    AppendUtf8(out, cp);
  }
  if (bytes.size() % 2) throw InputError(path, "UTF-16 text with an odd number of bytes: the file is cut short");
  return out;
}

}  // namespace

std::string DecodeText(std::string bytes, const std::string& path) {
  // Excel and Windows tools save "Unicode text" as UTF-16: read it as the UTF-8 it means.
  if (bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0xFF && static_cast<unsigned char>(bytes[1]) == 0xFE)
    bytes = Utf16ToUtf8(std::string_view(bytes).substr(2), true, path);
  else if (bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0xFE && static_cast<unsigned char>(bytes[1]) == 0xFF)
    bytes = Utf16ToUtf8(std::string_view(bytes).substr(2), false, path);
  else if (bytes.size() >= 4 && bytes[0] != 0 && bytes[1] == 0 && bytes[2] != 0 && bytes[3] == 0)
    bytes = Utf16ToUtf8(bytes, true, path);  // UTF-16LE without a byte-order mark
  if (bytes.rfind("PK\x03\x04", 0) == 0)
    throw InputError(path, "is a ZIP container (an .xlsx/.ods workbook?), not a text file: save the sheet as CSV");
  if (bytes.find('\0') != std::string::npos)
    throw InputError(path, "holds NUL bytes: a binary file, not text (or an encoding other than UTF-8/UTF-16)");
  // Classic Mac OS / some loggers end lines with CR alone: the readers count lines by LF.
  if (bytes.find('\n') == std::string::npos && bytes.find('\r') != std::string::npos)
    for (auto& c : bytes)
      if (c == '\r') c = '\n';
  return bytes;
}

std::string ReadFileBytes(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path, "is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, std::string("cannot open: ") + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string ReadTextFile(const std::string& path) { return DecodeText(ReadFileBytes(path), path); }

namespace {

// Where the finished file goes: the path, or a symlink's target; nullopt for a device, FIFO or
// socket (written through, not replaced).
std::optional<std::filesystem::path> ReplaceTarget(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);  // follows symlinks
  if (!fs::exists(st)) return fs::path(path);        // a new file
  if (fs::is_directory(st)) throw InputError(path, "is a directory, expected a file name to write");
  if (!fs::is_regular_file(st)) return std::nullopt;
  const fs::path real = fs::canonical(path, ec);
  return ec ? fs::path(path) : real;
}

}  // namespace

std::string TemporaryPathFor(const std::string& path) {
  const auto target = ReplaceTarget(path);
  if (target) return target->string() + ".tmp";
  return (std::filesystem::temp_directory_path() /
          ("trueaxis_" + std::to_string(::getpid()) + "_" + std::filesystem::path(path).filename().string() + ".tmp"))
      .string();
}

void CommitTemporaryFile(const std::string& tmp, const std::string& path) {
  std::error_code ec;
  const auto target = ReplaceTarget(path);
  if (!target) {
    {
      std::ifstream in(tmp, std::ios::binary);
      std::ofstream out(path, std::ios::binary);
      if (!in || !out) {
        std::filesystem::remove(tmp, ec);
        throw InputError(path, std::string("cannot write: ") + std::strerror(errno));
      }
      out << in.rdbuf();
      out.flush();
    }
    std::filesystem::remove(tmp, ec);
    return;
  }
  std::filesystem::rename(tmp, *target, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw InputError(path, "cannot replace file: " + ec.message());
  }
}

void WriteTextFile(const std::string& path, std::string_view content) {
  const std::string tmp = TemporaryPathFor(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path, std::string("cannot write: ") + std::strerror(errno));
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    if (!out) throw InputError(path, "write failed");
  }
  CommitTemporaryFile(tmp, path);
}

}  // namespace trueaxis
