#include "components/logging/npy_writer.h"

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace dmpl {
namespace {

constexpr size_t kHeaderBytes = 128;  // magic, version, length and the padded dict; 64-aligned

size_t ItemSize(const std::string& descr) {
  if (descr.size() == 3 && (descr[0] == '<' || descr[0] == '|')) return descr[2] - '0';
  throw std::invalid_argument("unsupported npy type '" + descr + "'");
}

}  // namespace

NpyColumn::NpyColumn(const std::string& path, const std::string& descr,
                     std::vector<size_t> row_shape)
    : path_(path), descr_(descr), row_shape_(std::move(row_shape)) {
  static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "npy columns are written little-endian");
  row_bytes_ = ItemSize(descr_);
  for (size_t d : row_shape_) row_bytes_ *= d;
  file_ = std::fopen(path_.c_str(), "wb");
  if (file_ == nullptr) {
    throw std::runtime_error("cannot create '" + path_ + "': " + std::strerror(errno));
  }
  const std::string header = Header();
  std::fwrite(header.data(), 1, header.size(), file_);
}

NpyColumn::~NpyColumn() {
  try {
    Close();
  } catch (const std::exception&) {
    // Close() already reported by throwing when called explicitly; a destructor cannot.
  }
}

std::string NpyColumn::Header() const {
  std::string shape = "(" + std::to_string(rows_) + ",";
  for (size_t d : row_shape_) shape += " " + std::to_string(d) + ",";
  if (!row_shape_.empty()) shape.pop_back();
  shape += ")";
  std::string dict =
      "{'descr': '" + descr_ + "', 'fortran_order': False, 'shape': " + shape + ", }";
  const size_t prefix = 10;  // magic (6), version (2), header length (2)
  if (prefix + dict.size() + 1 > kHeaderBytes) throw std::logic_error("npy header too long");
  dict.append(kHeaderBytes - prefix - dict.size() - 1, ' ');
  dict += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  const uint16_t len = static_cast<uint16_t>(dict.size());
  out += static_cast<char>(len & 0xff);
  out += static_cast<char>(len >> 8);
  return out + dict;
}

void NpyColumn::Append(const void* row) {
  std::fwrite(row, 1, row_bytes_, file_);
  ++rows_;
}

void NpyColumn::Close() {
  if (file_ == nullptr) return;
  std::FILE* f = file_;
  file_ = nullptr;
  const std::string header = Header();
  const bool ok = std::fflush(f) == 0 && !std::ferror(f) && std::fseek(f, 0, SEEK_SET) == 0 &&
                  std::fwrite(header.data(), 1, header.size(), f) == header.size();
  const bool closed = std::fclose(f) == 0;
  if (!ok || !closed) throw std::runtime_error("cannot write '" + path_ + "' (disk full?)");
}

}  // namespace dmpl
