#include "vtk_appended.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace invfem::detail {

// Arrays are copied from memory as they are: the files say byte_order="LittleEndian".
static_assert(std::endian::native == std::endian::little, "VTU output assumes a little-endian machine");

namespace {

void put_u64(std::string& out, std::size_t at, std::uint64_t v) { std::memcpy(out.data() + at, &v, sizeof v); }

void append_u64(std::string& out, std::uint64_t v) {
  out.resize(out.size() + sizeof v);
  put_u64(out, out.size() - sizeof v, v);
}

}  // namespace

VtkAppendedData::VtkAppendedData(int compression, std::size_t block_size)
    : compression_(compression), block_size_(block_size) {
  if (compression < 0 || compression > 9)
    throw std::invalid_argument("VTU compression " + std::to_string(compression) + " outside [0, 9]");
  // Whole words (8 bytes at most) per block, as VTK writes them; zlib counts in uLong/uInt.
  if (block_size == 0 || block_size % 8 != 0 || block_size > (std::size_t{1} << 30))
    throw std::invalid_argument("VTU block size " + std::to_string(block_size) +
                                " is not a positive multiple of 8 up to 2^30");
}

std::uint64_t VtkAppendedData::append(const void* data, std::size_t bytes) {
  const std::uint64_t offset = bytes_.size();
  const auto* p = static_cast<const unsigned char*>(data);
  if (compression_ > 0) {
    append_compressed(p, bytes);
  } else {
    append_u64(bytes_, bytes);
    bytes_.append(reinterpret_cast<const char*>(p), bytes);
  }
  return offset;
}

void VtkAppendedData::append_compressed(const unsigned char* data, std::size_t bytes) {
  const std::size_t blocks = (bytes + block_size_ - 1) / block_size_;
  const std::size_t header = bytes_.size();
  bytes_.resize(header + 8 * (3 + blocks));
  put_u64(bytes_, header, blocks);
  put_u64(bytes_, header + 8, block_size_);
  put_u64(bytes_, header + 16, bytes % block_size_);
  std::vector<unsigned char> out(compressBound(static_cast<uLong>(std::min(bytes, block_size_))));
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t begin = b * block_size_, size = std::min(block_size_, bytes - begin);
    uLongf written = static_cast<uLongf>(out.size());
    if (compress2(out.data(), &written, data + begin, static_cast<uLong>(size), compression_) != Z_OK)
      throw std::runtime_error("zlib could not compress a VTU block");
    put_u64(bytes_, header + 8 * (3 + b), written);
    bytes_.append(reinterpret_cast<const char*>(out.data()), written);
  }
}

}  // namespace invfem::detail
