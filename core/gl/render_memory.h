#pragma once
// What the GL driver keeps of renders that have finished, for a memory
// sample at a quiet point (session/walk.cpp, the soak's resident size).
namespace hw::gl {

// Makes the current context's driver let go of the working memory of its
// last finished render, and waits for that: a clear of a private 1×1
// target, then glFinish. llvmpipe (Mesa 22.3) frees a finished scene's
// binned triangles only when the context starts binning its next scene
// (lp_setup_get_empty_scene), so after a render of the whole scene they stay
// allocated until the next frame: 1–10 MiB at 64² in the indoor walk,
// depending on the view (docs/results/2026-12-03/soak/README.md). The clear
// starts that next scene (one clear command). Leaves the framebuffer,
// renderbuffer, scissor and colour-mask state as it found them; touches no
// pixel of any other target. Costs one tiny clear and a glFinish: call it
// where a memory sample is taken, not per frame. Needs a current context.
void releaseFinishedRenderMemory();

}  // namespace hw::gl
