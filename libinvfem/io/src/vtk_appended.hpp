#pragma once
// Private to the io part: the appended section of a VTK XML file, raw encoding, header_type
// UInt64, little endian. Arrays follow one another; a DataArray names where its own starts as
// `offset`, counted from the byte after the section's leading '_'. Each array is
//   uncompressed: UInt64 byte count, then the bytes;
//   zlib (compressor="vtkZLibDataCompressor"): UInt64 header [number of blocks, uncompressed
//     block size, uncompressed size of the last block (0 when it is full), compressed size of
//     each block], then the blocks, each compressed on its own (zlib stream, compress2).
// The layout of VTK's own vtkXMLWriter; VTK's reader reads it (tests/cli/frame_formats.py, VTK 9.1).
#include <cstddef>
#include <cstdint>
#include <string>

namespace invfem::detail {

class VtkAppendedData {
 public:
  // compression: 0 uncompressed, 1-9 zlib's level. block_size: uncompressed bytes per block.
  // Throws std::invalid_argument for a compression outside [0, 9] or a block size that is not a
  // positive multiple of 8 up to 2^30.
  VtkAppendedData(int compression, std::size_t block_size);

  // Appends `bytes` bytes at `data` as one array; returns its offset.
  std::uint64_t append(const void* data, std::size_t bytes);

  // The section's bytes after the '_'.
  const std::string& bytes() const { return bytes_; }
  bool compressed() const { return compression_ > 0; }

 private:
  void append_compressed(const unsigned char* data, std::size_t bytes);

  int compression_;
  std::size_t block_size_;
  std::string bytes_;
};

}  // namespace invfem::detail
