#include "scenes/obj_prescan.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace hw::scenes {
namespace {

TEST(ObjPrescan, CountsVerticesFacesAndReferences) {
  const std::string path = ::testing::TempDir() + "/prescan.obj";
  {
    std::ofstream f(path);
    f << "# comment f 1 2 3\nv 0 0 0\nv 1 0 0\r\nv 0 1 0\nvt 0 0\nvn 0 1 0\n"
         "f 1 2 3\nf\t1/1/1  2/1/1 3/1/1 1\nusemtl x\n";
  }
  auto c = countObjElements(path);
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(c->vertices, 3u);
  EXPECT_EQ(c->faces, 2u);
  EXPECT_EQ(c->references, 7u);
  EXPECT_EQ(objImportBytes(*c), 7u * 200 + 3u * 100);
  std::remove(path.c_str());
  EXPECT_FALSE(countObjElements(path));
}

}  // namespace
}  // namespace hw::scenes
