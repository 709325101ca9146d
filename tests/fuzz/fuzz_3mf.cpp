// libFuzzer target for the 3MF reader (untrusted zip + XML). Any input must give either an Error
// or a mesh that keeps RawMesh's contract: finite points, every index below the point count.
//
// Two modes, so that mutations reach the XML as well as the zip layer (a mutated deflate stream or
// CRC mostly stops at libzip): an input starting with "PK" is the whole .3mf archive; any other
// input is the 3D/3dmodel.model part, wrapped here into a valid package with libzip.
// Seeds: tests/fuzz/corpus/3mf/ (*.3mf archives, *.model parts).
//
// lib3mf 1.8.1 leaks 3 x 160 bytes per parsed package inside libzip (lib3mf issue #180, fixed in
// lib3mf 2.x), so run with -detect_leaks=0, or with ASAN_OPTIONS=fast_unwind_on_malloc=0 and an
// LSan suppression "leak:NMR::COpcPackageReader::openZIPEntryIndexed".
#include <zip.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "polyaxis/core/vec3.h"
#include "polyaxis/io/three_mf.h"

namespace {

constexpr std::string_view kContentTypes =
    R"(<?xml version="1.0" encoding="UTF-8"?><Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>)";
constexpr std::string_view kRels =
    R"(<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>)";

// A stored (uncompressed) package around MODEL; empty if libzip fails.
std::string wrap_model(std::string_view model) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* source = zip_source_buffer_create(nullptr, 0, 0, &error);
  if (source == nullptr) return {};
  zip_t* archive = zip_open_from_source(source, ZIP_TRUNCATE, &error);
  if (archive == nullptr) {
    zip_source_free(source);
    return {};
  }
  zip_source_keep(source);
  const std::pair<const char*, std::string_view> entries[] = {
      {"[Content_Types].xml", kContentTypes}, {"_rels/.rels", kRels}, {"3D/3dmodel.model", model}};
  for (const auto& [name, content] : entries) {
    zip_source_t* file = zip_source_buffer(archive, content.data(), content.size(), 0);
    const zip_int64_t index = file == nullptr ? -1 : zip_file_add(archive, name, file, 0);
    if (index < 0) {
      if (file != nullptr) zip_source_free(file);
      zip_discard(archive);
      zip_source_free(source);
      return {};
    }
    zip_set_file_compression(archive, static_cast<zip_uint64_t>(index), ZIP_CM_STORE, 0);
  }
  std::string out;
  if (zip_close(archive) != 0) {
    zip_discard(archive);
  } else if (zip_source_open(source) == 0) {
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_source_stat(source, &st) == 0) {
      out.resize(static_cast<std::size_t>(st.size));
      if (zip_source_read(source, out.data(), out.size()) != static_cast<zip_int64_t>(out.size())) out.clear();
    }
    zip_source_close(source);
  }
  zip_source_free(source);
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  std::string wrapped;
  std::string_view archive = input;
  if (!input.starts_with("PK")) {
    wrapped = wrap_model(input);
    if (wrapped.empty()) return 0;
    archive = wrapped;
  }
  polyaxis::io::ReadOptions options;
  options.max_triangles = 1'000'000;  // keeps each run short; the cap itself is under test too
  const auto result = polyaxis::io::read_3mf(archive, "fuzz.3mf", options);
  if (!result.ok()) return 0;
  const polyaxis::io::RawMesh& mesh = result.value().mesh;
  if (mesh.triangles.empty() || mesh.triangles.size() > options.max_triangles) __builtin_trap();
  for (const polyaxis::core::Vec3& p : mesh.points) {
    if (!polyaxis::core::is_finite(p)) __builtin_trap();
  }
  for (const polyaxis::io::Triangle& t : mesh.triangles) {
    for (const std::uint32_t i : t) {
      if (i >= mesh.points.size()) __builtin_trap();
    }
  }
  return 0;
}
