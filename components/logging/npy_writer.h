#pragma once
// A column of a table written to a NumPy .npy file row by row, so that a table of any length
// never has to be held in memory; the header (which carries the row count) is rewritten when the
// column is closed. numpy.load reads the file, memory-mapped if asked.
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace dmpl {

class NpyColumn {
 public:
  // descr: a little-endian NumPy type string ("<f8", "<i8", "<i4", "<i2", "|i1", "|b1");
  // row_shape: the shape of one row ({} for a scalar per row). Throws on I/O errors.
  NpyColumn(const std::string& path, const std::string& descr, std::vector<size_t> row_shape);
  ~NpyColumn();
  NpyColumn(const NpyColumn&) = delete;
  NpyColumn& operator=(const NpyColumn&) = delete;

  // Appends one row of row_bytes() bytes.
  void Append(const void* row);
  // Writes the final header and closes the file (also done by the destructor). Throws on I/O
  // errors (a full disk).
  void Close();

  size_t rows() const { return rows_; }
  size_t row_bytes() const { return row_bytes_; }
  const std::vector<size_t>& row_shape() const { return row_shape_; }

 private:
  std::string Header() const;
  std::string path_, descr_;
  std::vector<size_t> row_shape_;
  size_t row_bytes_ = 0;
  size_t rows_ = 0;
  std::FILE* file_ = nullptr;
};

}  // namespace dmpl
