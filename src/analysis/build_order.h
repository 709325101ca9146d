// The order regions are built in: each after every region its base lies on. Private to the
// analysis module (decompose.cpp).
#pragma once

#include <vector>

#include "polyaxis/analysis/decompose.h"

namespace polyaxis::analysis::detail {

// Fills each region's rests_on (its parent, and every region holding points just below its base
// cap: probes at the centroids of its largest cap facets, by winding number) and puts REGIONS in
// an order where each comes after all of those, keeping the given order where it can (Kahn's
// algorithm, lowest index first). Ids, parents and rests_on are renumbered to the new order. A
// cycle (not expected: a base lies on material already there) is broken at its lowest region,
// whose rests_on then loses the regions that come after it (never its parent).
// Cost O(probes · F).
void order_by_support(std::vector<Region>& regions);

}  // namespace polyaxis::analysis::detail
