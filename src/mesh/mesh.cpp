// Mesh is a plain aggregate; its helpers are inline in the header. This unit keeps the module's
// target non-empty and checks that the header stands alone.
#include "polyaxis/mesh/mesh.h"
