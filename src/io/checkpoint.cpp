// The checkpoint file:
//   "LINXCKPT"   8 bytes
//   version      u32 (kCheckpointVersion)
//   byte order   u32 0x01020304 as written by the machine that wrote it
//   length       u64 of the payload
//   payload      the RunCheckpoint's fields, state::Archive order (below)
//   checksum     u32 CRC-32 (zlib) of the payload
// Version 2 adds the identity of the run folder (RunCheckpoint::run_scene_bytes ... joints).
// A reader refuses anything else: another magic, version or byte order, a length that does not
// match the file's, a checksum that does not match the payload.
#include <linx/checkpoint.hpp>

#include "io/input_file.hpp"
#include "io/output_file.hpp"
#include "io/quoting.hpp"
#include "world/state_archive.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>
#include <zlib.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <system_error>

namespace linx {

namespace fs = std::filesystem;

namespace {

constexpr std::array<char, 8> kMagic = {'L', 'I', 'N', 'X', 'C', 'K', 'P', 'T'};
constexpr std::uint32_t kByteOrder = 0x01020304;
constexpr std::size_t kHeaderSize = 8 + 4 + 4 + 8, kTrailerSize = 4;
// The largest checkpoint read (a world of a million bodies takes about 1 GiB).
constexpr std::uint64_t kCheckpointLimit = 8 * io::kMiB * 1024;

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
           c.keep_going, c.frames, c.output.bytes, c.output.breaks, c.state.bytes,
           c.run_scene_bytes, c.run_scene_crc, c.bodies, c.joints);
}

template <class T>
void put(std::vector<std::byte>& out, const T& value) {
  const auto* p = reinterpret_cast<const std::byte*>(&value);
  out.insert(out.end(), p, p + sizeof value);
}

}  // namespace

std::uint32_t checksumOf(std::string_view text) {
  return crc32Of(std::as_bytes(std::span(text.data(), text.size())));
}

CheckpointError::CheckpointError(const std::string& file, const std::string& field,
                                 const std::string& problem)
    : std::runtime_error(io::visible(fmt::format("{}: {}: {}", file, field, problem))) {}

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

  io::writeFileAtomically(
      file, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

RunCheckpoint readCheckpoint(const fs::path& file) {
  const std::string name = file.string();
  std::string bytes;
  try {
    bytes = io::readInputFile(file, kCheckpointLimit, "a checkpoint");
  } catch (const std::runtime_error& e) {
    throw CheckpointError(name, "file", e.what());
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
        fmt::format("format version {}{}; this linx reads version {}", version,
                    version < kCheckpointVersion
                        ? " (an older linx's, which did not record its run folder: rerun the scene)"
                        : " (a newer linx's)",
                    kCheckpointVersion));
  if (const std::size_t held = bytes.size() - kHeaderSize - kTrailerSize; length != held)
    throw CheckpointError(name, "length",
                          fmt::format("the header says {} bytes of state, the file holds {} ({})",
                                      length, held, length > held ? "cut short?" : "appended to?"));
  const std::span<const std::byte> payload(
      reinterpret_cast<const std::byte*>(bytes.data()) + kHeaderSize, length);
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
      checkpoint.frames < 1 || checkpoint.bodies < 0 || checkpoint.joints < 0)
    throw CheckpointError(name, "run", "impossible step or frame counts");
  return checkpoint;
}

}  // namespace linx
