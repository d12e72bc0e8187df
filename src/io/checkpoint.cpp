// The checkpoint file:
//   "LINXCKPT"   8 bytes
//   version      u32 (kCheckpointVersion)
//   byte order   u32 0x01020304 as written by the machine that wrote it
//   length       u64 of the payload
//   payload      the RunCheckpoint's fields, state::Archive order (below)
//   checksum     u32 CRC-32 (zlib) of the payload
// A reader refuses anything else: another magic, version or byte order, a length that does not
// match the file's, a checksum that does not match the payload.
#include <linx/checkpoint.hpp>

#include "world/state_archive.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>
#include <zlib.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

namespace linx {

namespace fs = std::filesystem;

namespace {

constexpr std::array<char, 8> kMagic = {'L', 'I', 'N', 'X', 'C', 'K', 'P', 'T'};
constexpr std::uint32_t kByteOrder = 0x01020304;
constexpr std::size_t kHeaderSize = 8 + 4 + 4 + 8, kTrailerSize = 4;

std::uint32_t crc32Of(std::span<const std::byte> data) {
  uLong crc = crc32(0L, Z_NULL, 0);
  // zlib takes lengths as uInt: feed a large payload in pieces.
  while (!data.empty()) {
    const std::size_t n = std::min<std::size_t>(data.size(), 1u << 30);
    crc = crc32(crc, reinterpret_cast<const Bytef*>(data.data()), static_cast<uInt>(n));
    data = data.subspan(n);
  }
  return static_cast<std::uint32_t>(crc);
}

void persist(state::Archive& a, RunCheckpoint& c) {
  a.fields(c.scene, c.source, c.steps, c.every, c.checkpoint_every, c.contacts, c.breaks,
           c.keep_going, c.frames, c.output.bytes, c.output.breaks, c.state.bytes);
}

std::runtime_error ioError(const fs::path& path, int error) {
  return std::runtime_error(
      fmt::format("cannot write {}: {}", path.string(), std::generic_category().message(error)));
}

template <class T>
void put(std::vector<std::byte>& out, const T& value) {
  const auto* p = reinterpret_cast<const std::byte*>(&value);
  out.insert(out.end(), p, p + sizeof value);
}

}  // namespace

CheckpointError::CheckpointError(const std::string& file, const std::string& field,
                                 const std::string& problem)
    : std::runtime_error(fmt::format("{}: {}: {}", file, field, problem)) {}

void writeCheckpoint(const fs::path& file, const RunCheckpoint& checkpoint) {
  std::vector<std::byte> payload;
  state::Archive a = state::Archive::writer(payload);
  persist(a, const_cast<RunCheckpoint&>(checkpoint));  // a writer only reads
  std::vector<std::byte> bytes;
  bytes.reserve(kHeaderSize + payload.size() + kTrailerSize);
  for (const char c : kMagic) bytes.push_back(static_cast<std::byte>(c));
  put(bytes, kCheckpointVersion);
  put(bytes, kByteOrder);
  put(bytes, static_cast<std::uint64_t>(payload.size()));
  bytes.insert(bytes.end(), payload.begin(), payload.end());
  put(bytes, crc32Of(payload));

  const fs::path temp = file.parent_path() / fmt::format(".{}.tmp", file.filename().string());
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) throw ioError(temp, errno);
  std::span<const std::byte> rest = bytes;
  int error = 0;
  while (!rest.empty() && error == 0) {
    const ssize_t n = ::write(fd, rest.data(), rest.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      error = n < 0 ? errno : EIO;
    else
      rest = rest.subspan(static_cast<std::size_t>(n));
  }
  if (error == 0 && ::fsync(fd) != 0) error = errno;
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error == 0 && ::rename(temp.c_str(), file.c_str()) != 0) error = errno;
  if (error != 0) {
    ::unlink(temp.c_str());
    throw ioError(file, error);
  }
}

RunCheckpoint readCheckpoint(const fs::path& file) {
  const std::string name = file.string();
  std::error_code ec;
  if (fs::is_directory(file, ec)) throw CheckpointError(name, "file", "is a directory");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw CheckpointError(name, "file", std::strerror(errno));
  std::vector<std::byte> bytes;
  {
    std::vector<char> chunk(1 << 16);
    while (in.read(chunk.data(), static_cast<std::streamsize>(chunk.size())) || in.gcount() > 0) {
      const auto* p = reinterpret_cast<const std::byte*>(chunk.data());
      bytes.insert(bytes.end(), p, p + in.gcount());
      // The header says how long the file is: stop a file that is longer (or never ends).
      if (bytes.size() >= kHeaderSize) {
        std::uint64_t length = 0;
        std::memcpy(&length, bytes.data() + 16, sizeof length);
        if (length <= (std::uint64_t{1} << 40) &&
            bytes.size() > kHeaderSize + length + kTrailerSize)
          throw CheckpointError(name, "length", "the file is longer than its header says");
      }
    }
  }
  if (bytes.size() < kHeaderSize + kTrailerSize ||
      std::memcmp(bytes.data(), kMagic.data(), kMagic.size()) != 0)
    throw CheckpointError(name, "format", "not a linx checkpoint");
  std::uint32_t version = 0, order = 0;
  std::uint64_t length = 0;
  std::memcpy(&version, bytes.data() + 8, 4);
  std::memcpy(&order, bytes.data() + 12, 4);
  std::memcpy(&length, bytes.data() + 16, 8);
  if (order != kByteOrder)
    throw CheckpointError(name, "byte order", "written by a machine of another byte order");
  if (version != kCheckpointVersion)
    throw CheckpointError(
        name, "version",
        fmt::format("format version {}; this linx reads version {}", version, kCheckpointVersion));
  if (length != bytes.size() - kHeaderSize - kTrailerSize)
    throw CheckpointError(name, "length",
                          fmt::format("the header says {} bytes of state, the file holds {} "
                                      "(cut short?)",
                                      length, bytes.size() - kHeaderSize - kTrailerSize));
  const std::span<const std::byte> payload(bytes.data() + kHeaderSize, length);
  std::uint32_t checksum = 0;
  std::memcpy(&checksum, bytes.data() + kHeaderSize + length, 4);
  if (checksum != crc32Of(payload))
    throw CheckpointError(name, "checksum", "does not match: the file is damaged");
  RunCheckpoint checkpoint;
  try {
    state::Archive a = state::Archive::reader(payload);
    persist(a, checkpoint);
    if (!a.atEnd()) throw state::StateError("more than a checkpoint holds");
  } catch (const state::StateError& e) {
    throw CheckpointError(name, "state", e.what());
  }
  if (checkpoint.steps < 1 || checkpoint.every < 1 || checkpoint.checkpoint_every < 0 ||
      checkpoint.frames < 1)
    throw CheckpointError(name, "run", "impossible step or frame counts");
  return checkpoint;
}

}  // namespace linx
