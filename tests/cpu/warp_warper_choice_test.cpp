// Which warper `--warper auto` takes (warp/cpu_warper.h): the CPU warper only
// when GL_RENDERER names one of Mesa's CPU rasterisers, and only for options
// it draws.
#include <gtest/gtest.h>

#include <string>

#include "warp/cpu_warper.h"

namespace hw::warp {
namespace {

TEST(WarperChoice, CpuRasterisersAreRecognisedByTheirRendererString) {
  for (const char* r : {"llvmpipe (LLVM 15.0.6, 256 bits)", "softpipe", "Software Rasterizer",
                        "Mesa OffScreen", "zink (llvmpipe (LLVM 15.0.6, 256 bits))",
                        "SWR (LLVM 12.0.0, 256 bits)"}) {
    SCOPED_TRACE(r);
    EXPECT_TRUE(isSoftwareRasteriser(r));
  }
  for (const char* r : {"NVIDIA GeForce RTX 3080/PCIe/SSE2", "AMD Radeon RX 6800 (radeonsi, navi21, "
                        "LLVM 15.0.6, DRM 3.49)", "Mesa Intel(R) UHD Graphics 630 (CFL GT2)",
                        "virgl", ""}) {
    SCOPED_TRACE(r);
    EXPECT_FALSE(isSoftwareRasteriser(r));
  }
}

TEST(WarperChoice, NamesAndUnsupportedOptions) {
  EXPECT_STREQ(warperChoiceName(WarperChoice::Auto), "auto");
  EXPECT_STREQ(warperChoiceName(WarperChoice::Gl), "gl");
  EXPECT_STREQ(warperChoiceName(WarperChoice::Cpu), "cpu");
  WarpOptions o;  // the defaults: the CPU warper draws them
  EXPECT_EQ(cpuWarperUnsupported(o), "");
  o.texcoords = TexcoordMode::Affine;
  EXPECT_NE(cpuWarperUnsupported(o).find("affine"), std::string::npos);
  o = WarpOptions{};
  o.cullBackground = true;
  EXPECT_NE(cpuWarperUnsupported(o).find("--cull-background"), std::string::npos);
  EXPECT_FALSE(createCpuWarper(o).ok());
}

}  // namespace
}  // namespace hw::warp
