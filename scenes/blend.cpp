// .blend through Assimp with the node tree walked so that hidden nodes can
// be dropped; the import is tried in a child process first. See blend.h.
#include "scenes/blend.h"

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/texture.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>

#include <glm/glm.hpp>

#include "core/file_io.h"
#include "scenes/model_common.h"

namespace hw::scenes {
namespace {

namespace fs = std::filesystem;
using namespace detail;  // the readers' shared helpers (model_common.h)

struct BlendLoader {
  const aiScene* ai;
  std::string path;
  fs::path folder;
  BlendOptions options;
  Scene scene;
  ChunkBuilder builder;
  std::vector<int> materialOf;  // Assimp material → ours

  BlendLoader(const aiScene* s, std::string p, const BlendOptions& o)
      : ai(s),
        path(std::move(p)),
        folder(fs::path(path).parent_path()),
        options(o),
        builder(scene, o.chunkSizeMetres) {
    if (folder.empty()) folder = ".";
  }

  void materials() {
    bool warnedProcedural = false;
    for (unsigned i = 0; i < ai->mNumMaterials; ++i) {
      const aiMaterial& am = *ai->mMaterials[i];
      Material m;
      aiString name;
      if (am.Get(AI_MATKEY_NAME, name) == AI_SUCCESS) m.name = name.C_Str();
      aiColor4D c(0.8f, 0.8f, 0.8f, 1.0f);
      am.Get(AI_MATKEY_COLOR_DIFFUSE, c);
      m.baseColour = glm::vec4(c.r, c.g, c.b, 1.0f);
      m.twoSided = true;
      aiString tex;
      if (am.GetTexture(aiTextureType_DIFFUSE, 0, &tex) == AI_SUCCESS) {
        const std::string ref = tex.C_Str();
        Result<Image<Rgba8>> img = makeError("");
        bool procedural = false;
        if (ref.rfind("Procedural", 0) == 0) {
          procedural = true;
        } else if (const aiTexture* e = ai->GetEmbeddedTexture(ref.c_str())) {
          if (e->mHeight == 0) {
            img = decodeAnyImage(std::string(reinterpret_cast<const char*>(e->pcData), e->mWidth),
                                 path + " (embedded " + ref + ")");
          } else {
            Image<Rgba8> raw(static_cast<int>(e->mWidth), static_cast<int>(e->mHeight));
            for (std::size_t k = 0; k < raw.size(); ++k)
              raw.data()[k] = Rgba8{e->pcData[k].r, e->pcData[k].g, e->pcData[k].b, e->pcData[k].a};
            img = std::move(raw);
          }
        } else if (auto p = findTexture({folder}, ref)) {
          auto bytes = readFile(p->string());
          img = bytes ? decodeAnyImage(*bytes, p->string()) : Result<Image<Rgba8>>(bytes.error());
        } else {
          img = makeError(path + ": texture '" + ref + "' not found in " + folder.string());
        }
        if (procedural) {
          if (!warnedProcedural)
            scene.warnings.push_back(path +
                                     ": Blender procedural textures cannot be evaluated; their "
                                     "materials use the diffuse colour (first: " +
                                     m.name + ")");
          warnedProcedural = true;
        } else if (img.ok() && !img->empty()) {
          m.texture = static_cast<int>(scene.textures.size());
          m.alphaTest = hasCutout(*img);
          scene.textures.push_back(Texture{ref, std::move(*img)});
          m.baseColour = glm::vec4(1.0f);
        } else {
          scene.warnings.push_back(
              (img.ok() ? path + ": texture '" + ref + "' is empty" : img.error().message) +
              "; material '" + m.name + "' uses its diffuse colour");
        }
      }
      materialOf.push_back(static_cast<int>(scene.materials.size()));
      scene.materials.push_back(m);
    }
    if (scene.materials.empty()) scene.materials.push_back(Material{"default", glm::vec4(0.8f)});
  }

  glm::vec3 toYUp(const aiVector3D& v) const {
    return options.zUp ? glm::vec3(v.x, v.z, -v.y) : glm::vec3(v.x, v.y, v.z);
  }

  void node(const aiNode& n, const aiMatrix4x4& parent, int depth) {
    if (depth > 512) return;
    const std::string name = n.mName.C_Str();
    for (const std::string& h : options.hiddenNodes)
      if (h == name) return;
    bool ownMeshes = true;
    for (const std::string& h : options.hiddenNodePrefixes)
      if (name.rfind(h, 0) == 0) ownMeshes = false;
    const aiMatrix4x4 m = parent * n.mTransformation;
    aiMatrix3x3 nm(m);
    nm.Inverse().Transpose();
    std::vector<Vertex> verts;
    for (unsigned k = 0; ownMeshes && k < n.mNumMeshes; ++k) {
      const aiMesh& mesh = *ai->mMeshes[n.mMeshes[k]];
      if (!(mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
      verts.resize(mesh.mNumVertices);
      for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
        verts[v].position = toYUp(m * mesh.mVertices[v]);
        glm::vec3 nn(0, 1, 0);
        if (mesh.mNormals) {
          nn = toYUp(nm * mesh.mNormals[v]);
          const float len = glm::length(nn);
          nn = len > 0 && std::isfinite(len) ? nn / len : glm::vec3(0, 1, 0);
        }
        verts[v].normal = nn;
        verts[v].uv = mesh.mTextureCoords[0]
                          ? glm::vec2(mesh.mTextureCoords[0][v].x, mesh.mTextureCoords[0][v].y)
                          : glm::vec2(0.0f);
      }
      const int mat = mesh.mMaterialIndex < materialOf.size() ? materialOf[mesh.mMaterialIndex] : 0;
      builder.beginBatch();
      for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        if (face.mNumIndices != 3) continue;
        const unsigned a = face.mIndices[0], b = face.mIndices[1], c = face.mIndices[2];
        if (a >= verts.size() || b >= verts.size() || c >= verts.size() || a == b || b == c ||
            a == c || degenerate(verts[a].position, verts[b].position, verts[c].position))
          continue;
        builder.addTriangle(mat, verts, a, b, c);
      }
    }
    for (unsigned k = 0; k < n.mNumChildren; ++k) node(*n.mChildren[k], m, depth + 1);
  }
};

constexpr unsigned kBlendFlags = aiProcess_Triangulate | aiProcess_GenSmoothNormals |
                                 aiProcess_JoinIdenticalVertices | aiProcess_SortByPType |
                                 aiProcess_FlipUVs | aiProcess_ValidateDataStructure;

const aiScene* readBlend(Assimp::Importer& importer, const std::string& path,
                         unsigned flags = kBlendFlags) {
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  return importer.ReadFile(path, flags);
}

// Assimp 5's Blender importer follows the file's pointers and block sizes
// without checking them all: it segfaults on some real files (the MORSE
// environments human_tut/tutorial_scene and sandbox) and on damaged ones. A
// crash cannot be caught in the process, so the import is first tried in a
// forked child; this process imports the file only when the child came
// through (whether or not Assimp accepted the file: its own error message is
// then the one to show). The child only reads and validates (no
// triangulation, normals or vertex joining: those run on validated data):
// tum_kitchen (266k triangles) loads in 3.8–4.3 s instead of 2.4–3.2 s
// (5.1 s with a full second import; all on a loaded machine).
Status tryBlendImportInChild(const std::string& path) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) return {};  // no child: import here, as without the guard
  if (pid == 0) {
    // The parent's SIGINT/SIGTERM handler would remove the parent's
    // temporaries; the child has none of its own. It dies with the parent,
    // leaves no core file and says nothing (sanitizer reports included).
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGTERM, SIG_DFL);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    const rlimit noCore{0, 0};
    ::setrlimit(RLIMIT_CORE, &noCore);
    const int devNull = ::open("/dev/null", O_WRONLY);
    if (devNull >= 0) {
      ::dup2(devNull, 1);
      ::dup2(devNull, 2);
    }
    int code = 0;
    try {
      Assimp::Importer importer;
      code = readBlend(importer, path, aiProcess_ValidateDataStructure) ? 0 : 3;
    } catch (...) {
      code = 3;
    }
    ::_exit(code);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return {};
  const char* how = nullptr;
  std::string detail;
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    detail = sig == SIGSEGV ? "SIGSEGV" : sig == SIGBUS ? "SIGBUS" : sig == SIGABRT ? "SIGABRT"
             : sig == SIGKILL ? "SIGKILL (out of memory?)" : "signal " + std::to_string(sig);
    how = "crashed";
  } else if (WIFEXITED(status) && WEXITSTATUS(status) != 0 && WEXITSTATUS(status) != 3) {
    detail = "exit status " + std::to_string(WEXITSTATUS(status));  // e.g. a sanitizer's report
    how = "failed";
  }
  if (!how) return {};
  return makeError(path + ": Assimp's Blender importer " + how + " reading this file (" + detail +
                   " in a child process that tries each .blend first); not loaded (expected a "
                   ".blend that Assimp 5 imports: re-save it from Blender 2.7x, or export it "
                   "as glTF or OBJ)");
}

}  // namespace

Result<Scene> loadBlendFile(const std::string& path, const BlendOptions& options) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return makeError(path + ": no such file");
  HW_TRY(tryBlendImportInChild(path));
  try {
    Assimp::Importer importer;
    const aiScene* ai = readBlend(importer, path);
    if (!ai) return makeError(path + ": Assimp cannot read it: " + importer.GetErrorString());
    if (!ai->mRootNode) return makeError(path + ": Assimp returned no node tree");
    BlendLoader l(ai, path, options);
    l.scene.name = fs::path(path).stem().string();
    l.materials();
    l.node(*ai->mRootNode, aiMatrix4x4(), 0);
    if (l.scene.meshes.empty()) return makeError(path + ": no triangles outside the hidden nodes");
    l.scene.computeBounds();
    return std::move(l.scene);
  } catch (const std::exception& e) {
    return makeError(path + ": cannot read .blend: " + e.what());
  } catch (...) {
    return makeError(path + ": cannot read .blend: unknown error");
  }
}

}  // namespace hw::scenes
