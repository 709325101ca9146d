#include "polyaxis/io/zip_archive.h"

#include <fmt/format.h>
#include <zip.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>

#include "polyaxis/core/tolerances.h"

namespace polyaxis::io {
namespace {

using core::ErrorCode;
using core::make_error;

// Entries below this many uncompressed bytes skip the ratio test: a few kB of XML may compress
// far better than 1000:1 relative to a tiny file without being a threat.
constexpr std::uint64_t kRatioCheckFloorBytes = 4ull << 20;
// libzip opens an empty buffer as a new, empty archive; anything shorter than the 22-byte
// end-of-central-directory record cannot be a zip file.
constexpr std::size_t kMinZipBytes = 22;

core::Error invalid(std::string message) { return make_error(ErrorCode::kInvalidInput, std::move(message)); }

std::string reason(zip_error_t* error) {
  std::string text = zip_error_strerror(error);
  zip_error_fini(error);
  return text;
}

struct ArchiveCloser {
  void operator()(zip_t* z) const { zip_discard(z); }
};
using Archive = std::unique_ptr<zip_t, ArchiveCloser>;

// The uncompressed bytes of entry INDEX, which the directory says are SIZE; false when the entry
// is corrupt or holds more or less than that.
bool read_entry(zip_t* zip, zip_uint64_t index, zip_uint64_t size, std::string& out) {
  zip_file_t* file = zip_fopen_index(zip, index, 0);
  if (file == nullptr) return false;
  out.resize(static_cast<std::size_t>(size));
  std::size_t done = 0;
  bool ok = true;
  while (done < out.size()) {
    const zip_int64_t n = zip_fread(file, out.data() + done, out.size() - done);
    if (n <= 0) {
      ok = false;
      break;
    }
    done += static_cast<std::size_t>(n);
  }
  char extra = 0;
  if (ok && zip_fread(file, &extra, 1) != 0) ok = false;  // more data than the directory declares
  zip_fclose(file);
  return ok;
}

}  // namespace

core::Result<std::vector<ZipEntry>> read_zip(std::string_view data, const std::string& name, std::string_view kind,
                                             const std::function<bool(std::string_view path)>& want) {
  if (data.size() < kMinZipBytes) return invalid(fmt::format("{}: not a zip archive, so not {} ({} bytes)", name, kind, data.size()));
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* source = zip_source_buffer_create(data.data(), data.size(), 0, &error);
  if (source == nullptr) return invalid(fmt::format("{}: not a zip archive, so not {} ({})", name, kind, reason(&error)));
  Archive zip(zip_open_from_source(source, ZIP_RDONLY, &error));
  if (zip == nullptr) {
    zip_source_free(source);
    return invalid(fmt::format("{}: not a zip archive, so not {} ({})", name, kind, reason(&error)));
  }
  zip_error_fini(&error);
  const zip_int64_t count = zip_get_num_entries(zip.get(), 0);
  if (count < 0) return invalid(fmt::format("{}: unreadable zip directory", name));
  if (static_cast<std::uint64_t>(count) > kMaxZipEntries) {
    return invalid(fmt::format("{}: zip archive has {} entries (more than {}); refused", name, count, kMaxZipEntries));
  }
  std::uint64_t total = 0;
  std::vector<ZipEntry> entries;
  std::vector<zip_uint64_t> sizes;
  for (zip_uint64_t i = 0; i < static_cast<zip_uint64_t>(count); ++i) {
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_stat_index(zip.get(), i, 0, &st) != 0 || (st.valid & ZIP_STAT_SIZE) == 0 || (st.valid & ZIP_STAT_COMP_SIZE) == 0) {
      return invalid(fmt::format("{}: zip entry {} has no readable size", name, i));
    }
    const char* entry_name = (st.valid & ZIP_STAT_NAME) != 0 && st.name != nullptr ? st.name : "";
    if (st.size > core::kMax3mfUncompressedBytes - std::min(total, core::kMax3mfUncompressedBytes)) {
      return invalid(fmt::format("{}: zip entries expand to more than {} bytes (entry '{}' alone {}); refused as a possible zip bomb", name,
                                 core::kMax3mfUncompressedBytes, entry_name, st.size));
    }
    total += st.size;
    if (st.size > kRatioCheckFloorBytes) {
      const double ratio = static_cast<double>(st.size) / static_cast<double>(std::max<zip_uint64_t>(st.comp_size, 1));
      if (ratio > core::kMax3mfCompressionRatio) {
        return invalid(fmt::format("{}: zip entry '{}' expands {:.0f}:1 ({} bytes from {}); refused as a possible zip bomb (limit {:.0f}:1)",
                                   name, entry_name, ratio, st.size, st.comp_size, core::kMax3mfCompressionRatio));
      }
    }
    if (want(entry_name)) {
      entries.push_back(ZipEntry{i, entry_name, {}});
      sizes.push_back(st.size);
    }
  }
  if (total > kRatioCheckFloorBytes) {
    const double ratio = static_cast<double>(total) / static_cast<double>(std::max<std::size_t>(data.size(), 1));
    if (ratio > core::kMax3mfCompressionRatio) {
      return invalid(fmt::format("{}: archive expands {:.0f}:1 ({} bytes from {}); refused as a possible zip bomb (limit {:.0f}:1)", name, ratio,
                                 total, data.size(), core::kMax3mfCompressionRatio));
    }
  }
  for (std::size_t k = 0; k < entries.size(); ++k) {
    if (!read_entry(zip.get(), entries[k].index, sizes[k], entries[k].bytes)) {
      return invalid(fmt::format("{}: part '{}' is corrupt or not {} bytes as declared", name, entries[k].path, sizes[k]));
    }
  }
  return entries;
}

namespace {

// 1980-01-01 00:00 local time: the earliest time a zip directory holds, the same for every run
// (libzip writes local time).
std::time_t zip_epoch() {
  std::tm epoch{};
  epoch.tm_year = 80, epoch.tm_mday = 1, epoch.tm_isdst = -1;
  return std::mktime(&epoch);
}

// Adds (or, with REPLACE, replaces) the entry PATH holding BYTES, deflated and stamped at the
// epoch; BYTES must outlive zip_close. False on failure (zip_strerror says why).
bool put_entry(zip_t* archive, const std::string& path, std::string_view bytes, bool replace) {
  zip_source_t* part = zip_source_buffer(archive, bytes.data(), bytes.size(), 0);
  if (part == nullptr) return false;
  zip_int64_t index = -1;
  if (replace) {
    index = zip_name_locate(archive, path.c_str(), 0);
    if (index < 0 || zip_file_replace(archive, static_cast<zip_uint64_t>(index), part, 0) != 0) index = -1;
  } else {
    index = zip_file_add(archive, path.c_str(), part, ZIP_FL_ENC_UTF_8);
  }
  if (index < 0) {
    zip_source_free(part);
    return false;
  }
  return zip_set_file_compression(archive, static_cast<zip_uint64_t>(index), ZIP_CM_DEFLATE, 6) == 0 &&
         zip_file_set_mtime(archive, static_cast<zip_uint64_t>(index), zip_epoch(), 0) == 0;
}

// Opens the archive in DATA (a new one when DATA is empty) in memory, lets EDIT change it, and
// returns the bytes written. kInternal naming what failed.
core::Result<std::string> rewrite_zip(std::string_view data, const std::function<std::string(zip_t*)>& edit) {
  auto fail = [](const std::string& what, const std::string& why) {
    return make_error(ErrorCode::kInternal, fmt::format("cannot write the zip archive ({}: {})", what, why));
  };
  zip_error_t error;
  zip_error_init(&error);
  // libzip gets its own copy to free: rewriting an archive in a buffer, it keeps the unchanged
  // prefix's fragment in the new buffer and frees it with it (libzip 1.7), whoever owned it.
  void* copy = nullptr;
  if (!data.empty()) {
    copy = std::malloc(data.size());
    if (copy == nullptr) return fail("buffer", "out of memory");
    std::memcpy(copy, data.data(), data.size());
  }
  zip_source_t* source = zip_source_buffer_create(copy, data.size(), copy != nullptr ? 1 : 0, &error);
  if (source == nullptr) {
    std::free(copy);
    return fail("buffer", reason(&error));
  }
  zip_t* archive = zip_open_from_source(source, data.empty() ? ZIP_TRUNCATE : 0, &error);
  if (archive == nullptr) {
    zip_source_free(source);
    return fail("open", reason(&error));
  }
  zip_error_fini(&error);
  zip_source_keep(source);  // the archive's bytes are read back from it after zip_close
  std::string what = edit(archive);
  if (what.empty() && zip_close(archive) != 0) what = "close";
  if (!what.empty()) {
    std::string why = zip_strerror(archive);
    zip_discard(archive);
    zip_source_free(source);
    return fail(what, why);
  }
  std::string out;
  if (zip_source_open(source) != 0) {
    zip_source_free(source);
    return fail("read back", "cannot reopen the buffer");
  }
  zip_stat_t st;
  zip_stat_init(&st);
  if (zip_source_stat(source, &st) == 0 && (st.valid & ZIP_STAT_SIZE) != 0) {
    out.resize(static_cast<std::size_t>(st.size));
    std::size_t done = 0;
    while (done < out.size()) {
      const zip_int64_t n = zip_source_read(source, out.data() + done, out.size() - done);
      if (n <= 0) break;
      done += static_cast<std::size_t>(n);
    }
    out.resize(done);
  }
  zip_source_close(source);
  zip_source_free(source);
  if (out.empty()) return fail("read back", "no bytes");
  return out;
}

}  // namespace

core::Result<std::string> write_zip(std::span<const std::pair<std::string, std::string>> entries) {
  return rewrite_zip({}, [&](zip_t* archive) -> std::string {
    for (const auto& [path, bytes] : entries) {
      if (!put_entry(archive, path, bytes, false)) return path;
    }
    return {};
  });
}

core::Result<std::string> replace_zip_entries(std::string_view data, std::span<const std::pair<std::string, std::string>> entries) {
  return rewrite_zip(data, [&](zip_t* archive) -> std::string {
    for (const auto& [path, bytes] : entries) {
      if (!put_entry(archive, path, bytes, true)) return path;
    }
    return {};
  });
}

core::Result<std::string> replace_zip_entry(std::string_view data, const std::string& path, std::string_view bytes) {
  const std::pair<std::string, std::string> entry{path, std::string(bytes)};
  return replace_zip_entries(data, std::span(&entry, 1));
}

}  // namespace polyaxis::io
