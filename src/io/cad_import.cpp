// STEP (ISO 10303-21) and IGES import through OpenCASCADE 7.6: read, transfer all roots into one
// shape, tessellate with BRepMesh_IncrementalMesh, collect every face's Poly_Triangulation.
// This is the only translation unit that sees OpenCASCADE headers (src/CMakeLists.txt); it is
// linked only into the polyaxis-cad-import helper executable, never into polyaxis_io.
#include "cad_import.h"

#include <unistd.h>

#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <Bnd_Box.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <BRep_Tool.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TopAbs_Orientation.hxx>
#include <TopAbs_ShapeEnum.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <XSControl_Reader.hxx>
#include <fmt/format.h>
#include <gp_Pnt.hxx>
#include <gp_Trsf.hxx>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <memory>
#include <new>
#include <string_view>
#include <utility>
#include <vector>

namespace polyaxis::io {
namespace {

using core::ErrorCode;
using core::make_error;

constexpr double kPi = 3.14159265358979323846;

// Buffered writes to the result file; remembers the first failure.
class ResultWriter {
 public:
  explicit ResultWriter(int fd) : fd_(fd) { buffer_.reserve(kBufferBytes); }

  void put(const void* data, std::size_t size) {
    const char* p = static_cast<const char*>(data);
    while (size > 0 && ok_) {
      const std::size_t n = std::min(size, kBufferBytes - buffer_.size());
      buffer_.insert(buffer_.end(), p, p + n);
      p += n;
      size -= n;
      if (buffer_.size() == kBufferBytes) flush();
    }
  }
  void put_u32(std::uint32_t v) { put(&v, sizeof v); }
  void put_u64(std::uint64_t v) { put(&v, sizeof v); }
  void put_string(std::string_view s) {
    put_u64(s.size());
    put(s.data(), s.size());
  }

  bool finish() {
    flush();
    return ok_;
  }

 private:
  static constexpr std::size_t kBufferBytes = 64u << 10;

  void flush() {
    std::size_t done = 0;
    while (done < buffer_.size() && ok_) {
      const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        ok_ = false;
        break;
      }
      done += static_cast<std::size_t>(n);
    }
    buffer_.clear();
  }

  int fd_;
  std::vector<char> buffer_;
  bool ok_ = true;
};

core::Error fail(const char* kind, const std::string& what, const std::string& path) {
  return make_error(ErrorCode::kInvalidInput, fmt::format("{} import failed: {} ({})", kind, what, path));
}

// Reads and transfers the file; a null shape means nothing was transferred.
core::Result<TopoDS_Shape> read_shape(const std::string& path, Format format, const char* kind) {
  std::unique_ptr<XSControl_Reader> reader;
  if (format == Format::kStep) {
    reader = std::make_unique<STEPControl_Reader>();
  } else {
    reader = std::make_unique<IGESControl_Reader>();
  }
  const IFSelect_ReturnStatus status = reader->ReadFile(path.c_str());
  if (status != IFSelect_RetDone) return fail(kind, "syntax error or unreadable", path);
  if (reader->NbRootsForTransfer() <= 0) return fail(kind, "no solid or surface geometry (no entity to transfer)", path);
  reader->TransferRoots();
  if (reader->NbShapes() <= 0) return fail(kind, "no solid or surface geometry", path);
  TopoDS_Shape shape = reader->OneShape();
  if (shape.IsNull()) return fail(kind, "no solid or surface geometry", path);
  return shape;
}

// Edges bounding one face only: where faces that meet were not joined (an IGES file of trimmed
// surfaces carries no topology at all).
int free_edges(const TopoDS_Shape& shape) {
  TopTools_IndexedDataMapOfShapeListOfShape faces_of_edge;
  TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, faces_of_edge);
  int free = 0;
  for (int i = 1; i <= faces_of_edge.Extent(); ++i) {
    if (faces_of_edge(i).Extent() == 1 && !BRep_Tool::Degenerated(TopoDS::Edge(faces_of_edge.FindKey(i)))) ++free;
  }
  return free;
}

// SHAPE with its faces sewn along the edges they share, when it has free edges: each shared edge
// is then one edge, tessellated once, so that the faces' meshes meet node for node (unsewn, each
// face cut its own edges and the mesh came out with holes of dozens of edges). The tolerance is
// 1e-4 of the part's diagonal (0.01 mm on a 100 mm part), at least the file's own edge tolerance.
TopoDS_Shape sewn(const TopoDS_Shape& shape, std::vector<std::string>* warnings, const std::string& path) {
  const int before = free_edges(shape);
  if (before == 0) return shape;
  Bnd_Box box;
  BRepBndLib::Add(shape, box);
  if (box.IsVoid()) return shape;
  const double diagonal = std::sqrt(box.SquareExtent());
  const double tolerance = std::clamp(std::max(1e-4 * diagonal, BRep_Tool::MaxTolerance(shape, TopAbs_EDGE)), 1e-7, 0.1 * diagonal);
  BRepBuilderAPI_Sewing sewing(tolerance);
  sewing.Add(shape);
  sewing.Perform();
  const TopoDS_Shape result = sewing.SewedShape();
  if (result.IsNull() || !TopExp_Explorer(result, TopAbs_FACE).More()) return shape;
  const int after = free_edges(result);
  if (warnings != nullptr) {
    warnings->push_back(fmt::format("{}: faces sewn along their shared edges (tolerance {:.3g} mm): {} free edges before, {} after", path,
                                    tolerance, before, after));
  }
  return result;
}

core::Result<RawMesh> import_unguarded(const std::string& path, Format format, double chordal_mm,
                                       double angular_deg, std::vector<std::string>* warnings) {
  const char* kind = format == Format::kIges ? "IGES" : "STEP";
  if (format != Format::kStep && format != Format::kIges) {
    return make_error(ErrorCode::kUsage, fmt::format("CAD import of {}: format is neither STEP nor IGES", path));
  }
  if (!(chordal_mm > 0.0) || !std::isfinite(chordal_mm)) {
    return make_error(ErrorCode::kUsage, fmt::format("{} import of {}: chordal tolerance {} mm must be positive",
                                                     kind, path, chordal_mm));
  }
  if (!(angular_deg > 0.0) || !(angular_deg < 180.0)) {
    return make_error(ErrorCode::kUsage, fmt::format("{} import of {}: angular tolerance {} deg must be in (0, 180)",
                                                     kind, path, angular_deg));
  }

  auto shape_or = read_shape(path, format, kind);
  if (!shape_or) return shape_or.error();
  const TopoDS_Shape shape = sewn(shape_or.value(), warnings, path);

  if (!TopExp_Explorer(shape, TopAbs_FACE).More()) return fail(kind, "no solid or surface geometry (no face)", path);
  if (!TopExp_Explorer(shape, TopAbs_SOLID).More() && warnings != nullptr && free_edges(shape) > 0) {
    warnings->push_back(fmt::format("{}: {} file holds surfaces but no solid; the mesh may be open", path, kind));
  }

  const double angular_rad = angular_deg * kPi / 180.0;
  BRepMesh_IncrementalMesh mesher(shape, chordal_mm, /*isRelative=*/false, angular_rad, /*isInParallel=*/false);
  if (!mesher.IsDone()) return fail(kind, "tessellation failed", path);

  RawMesh mesh;
  std::size_t face_index = 0;
  std::size_t faces_without_mesh = 0;
  for (TopExp_Explorer explorer(shape, TopAbs_FACE); explorer.More(); explorer.Next(), ++face_index) {
    const TopoDS_Face& face = TopoDS::Face(explorer.Current());
    TopLoc_Location location;
    const Handle(Poly_Triangulation) triangulation = BRep_Tool::Triangulation(face, location);
    if (triangulation.IsNull() || triangulation->NbTriangles() <= 0) {
      ++faces_without_mesh;
      continue;
    }
    const gp_Trsf transform = location.Transformation();
    const bool reversed = face.Orientation() == TopAbs_REVERSED;
    const int node_count = triangulation->NbNodes();
    const std::size_t base = mesh.points.size();
    if (base + static_cast<std::size_t>(node_count) > std::numeric_limits<std::uint32_t>::max()) {
      return fail(kind, "more than 2^32 tessellation nodes", path);
    }
    for (int i = 1; i <= node_count; ++i) {
      const gp_Pnt p = triangulation->Node(i).Transformed(transform);
      const core::Vec3 v{p.X(), p.Y(), p.Z()};
      if (!core::is_finite(v)) return fail(kind, fmt::format("non-finite tessellation node in face {}", face_index), path);
      mesh.points.push_back(v);
    }
    for (int t = 1; t <= triangulation->NbTriangles(); ++t) {
      int a = 0;
      int b = 0;
      int c = 0;
      triangulation->Triangle(t).Get(a, b, c);
      if (a < 1 || b < 1 || c < 1 || a > node_count || b > node_count || c > node_count) {
        return fail(kind, fmt::format("tessellation of face {} has a bad node index", face_index), path);
      }
      if (reversed) std::swap(b, c);
      mesh.triangles.push_back({static_cast<std::uint32_t>(base + static_cast<std::size_t>(a - 1)),
                                static_cast<std::uint32_t>(base + static_cast<std::size_t>(b - 1)),
                                static_cast<std::uint32_t>(base + static_cast<std::size_t>(c - 1))});
    }
  }
  if (mesh.triangles.empty()) return fail(kind, "no solid or surface geometry (nothing tessellated)", path);
  if (faces_without_mesh > 0 && warnings != nullptr) {
    warnings->push_back(fmt::format("{}: {} of {} {} faces could not be tessellated and were skipped", path,
                                    faces_without_mesh, face_index, kind));
  }
  return mesh;
}

}  // namespace

core::Result<RawMesh> import_cad_file(const std::string& path, Format format, double chordal_mm,
                                      double angular_deg, std::vector<std::string>* warnings) {
  const char* kind = format == Format::kIges ? "IGES" : "STEP";
  // OpenCASCADE reports through Standard_Failure (not a std::exception) and std::bad_alloc.
  try {
    return import_unguarded(path, format, chordal_mm, angular_deg, warnings);
  } catch (const Standard_Failure& failure) {
    const char* what = failure.GetMessageString();
    return fail(kind, fmt::format("OpenCASCADE exception {}: {}", failure.DynamicType()->Name(),
                                  what != nullptr ? what : ""),
                path);
  } catch (const std::bad_alloc&) {
    return fail(kind, "out of memory", path);
  } catch (const std::exception& e) {
    return fail(kind, fmt::format("exception: {}", e.what()), path);
  } catch (...) {
    return fail(kind, "unknown exception", path);
  }
}

int import_cad_to_fd(int result_fd, const std::string& path, Format format, double chordal_mm, double angular_deg) {
  namespace p = cad_protocol;
  try {
    std::vector<std::string> warnings;
    auto mesh_or = import_cad_file(path, format, chordal_mm, angular_deg, &warnings);
    ResultWriter out(result_fd);
    out.put(p::kMagic, sizeof p::kMagic);
    if (!mesh_or.ok()) {
      out.put_u32(p::kStatusError);
      out.put_string(mesh_or.error().message);
      return out.finish() ? p::kExitImportError : p::kExitWriteFailed;
    }
    const RawMesh& mesh = mesh_or.value();
    out.put_u32(p::kStatusOk);
    out.put_u64(warnings.size());
    for (const std::string& w : warnings) out.put_string(w);
    out.put_u64(mesh.points.size());
    out.put_u64(mesh.triangles.size());
    for (const core::Vec3& pt : mesh.points) {
      const double xyz[3] = {pt.x, pt.y, pt.z};
      out.put(xyz, sizeof xyz);
    }
    static_assert(sizeof(Triangle) == 12);
    out.put(mesh.triangles.data(), mesh.triangles.size() * sizeof(Triangle));
    return out.finish() ? p::kExitOk : p::kExitWriteFailed;
  } catch (const std::bad_alloc&) {
    return p::kExitOutOfMemory;
  } catch (...) {
    return p::kExitException;
  }
}

}  // namespace polyaxis::io
