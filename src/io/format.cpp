#include "polyaxis/io/raw_mesh.h"

namespace polyaxis::io {

std::string_view format_name(Format format) {
  switch (format) {
    case Format::kStlBinary: return "stl-binary";
    case Format::kStlAscii: return "stl-ascii";
    case Format::kObj: return "obj";
    case Format::k3mf: return "3mf";
    case Format::kStep: return "step";
    case Format::kIges: return "iges";
  }
  return "unknown";
}

}  // namespace polyaxis::io
