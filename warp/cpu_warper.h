#pragma once
// A warper on the CPU, for machines whose OpenGL is itself a CPU rasteriser
// (llvmpipe): the same quads, texcoords and overlay rule as the GL warper
// (warp/gl/warper.cpp), rasterised by a routine specialised for them. Where
// llvmpipe spends about 2 µs setting up each quad and reads the layer back,
// this one sets a quad up in well under a microsecond and writes the layer
// where the frame is composed. Pixels agree with the GL warper's to within
// rounding: bilinear weights, depth ties and edge pixels may differ by a
// level or a pixel (tests/gl/warp_cpu_test.cpp bounds it).
//
// Supports the default warp options: one quad per leaf (no subdivision),
// projective texcoords, any indexed or independent primitives (they draw
// the same triangles), the sky backdrop on or off, large leaves marked, eye
// z on request. Not: subdivision, affine texcoords, points, the background
// cull (cpuWarperSupports says which).
#include <memory>
#include <string>

#include "core/result.h"
#include "warp/warper.h"

namespace hw::warp {

// Which warper draws the layers (walk/view --warper).
enum class WarperChoice {
  Auto,  // the CPU warper where OpenGL is itself a CPU rasteriser and the
         // options allow it (isSoftwareRasteriser), else the GL warper
  Gl,
  Cpu,
};
const char* warperChoiceName(WarperChoice c);  // "auto", "gl", "cpu"

// Whether GL_RENDERER names a CPU rasteriser (Mesa's llvmpipe, softpipe,
// classic swrast, OpenSWR), where the CPU warper is the faster one.
bool isSoftwareRasteriser(const std::string& glRenderer);

// Empty when `options` can be warped on the CPU, else what cannot.
std::string cpuWarperUnsupported(const WarpOptions& options);

// `threads` >= 1: the threads set up the quads between them, then each
// draws a band of the target's rows (bands cut so their estimated work is
// even); pixels and counts do not depend on the number. The threads start
// here (an error if one cannot). `simd`: 8 pixels at a time where the CPU
// has AVX2 (else, or false, one at a time; the same pixels to within a
// level). Error when cpuWarperUnsupported(options) is not empty.
Result<std::unique_ptr<Warper>> createCpuWarper(const WarpOptions& options, int threads = 1,
                                                bool simd = true);

}  // namespace hw::warp
