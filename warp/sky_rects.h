#pragma once
// Empty keyframe pixels (nothing drawn: sky) as a few rectangles, so the warp
// can draw them as quads at infinity — the paper's far-plane regions, placed
// where points at infinity really are (they move only with camera rotation).
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "keyframe/quad_mesh.h"

namespace hw::warp {

// Rectangles covering exactly the pixels with covered == 0, without overlap:
// runs of empty pixels per row, merged with the identical run of the row above.
void emptyRects(const Image<std::uint8_t>& covered, std::vector<keyframe::PixelRect>& out);

}  // namespace hw::warp
