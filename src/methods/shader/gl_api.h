// Internal to gl/: the OpenGL and EGL headers, the process's one headless context and the
// GL error helpers that methods/shader/context.cpp, methods/shader/program.cpp,
// methods/shader/glsl_method.cpp and methods/shader/timed_draws.cpp share.
#pragma once

#define EGL_EGLEXT_PROTOTYPES
#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include <functional>
#include <mutex>
#include <string>

#include "methods/shader/glsl_method.h"

namespace pgt::gl {

// Guards the device choice and the context's state.
extern std::mutex gMutex;
// Creates the context on first use and makes it current on this thread (the GL thread,
// holding gMutex); rethrows why it could not be made.
void ensureContext();
// Runs `job` on the process's one GL thread, which owns the context (made current there
// once, on first use), and waits for it; rethrows what the job threw. Any thread may call it
// (a study's cases run concurrently, and a context can be current on one thread only);
// jobs run one at a time, and a job may call it again (it then runs inline).
void onGlThread(const std::function<void()>& job);

// The context's renderer, as glContext() returns it (after ensureContext()).
const GlInfo& contextInfo();
// Throws std::runtime_error naming `what` when GL reports an error.
void checkGl(const std::string& what);
// Any GL error left by an earlier call is reported there; start each step clean so that a
// later check blames only its own calls.
void drainGlErrors();
// A 2D float texture, level 0 from `data` (null: undefined), one filter for both directions,
// one wrap mode, no further levels (methods/shader/map_uploads.cpp).
GLuint makeTexture(GLenum internal, GLenum format, int w, int h, const void* data, GLenum filter,
                   GLenum wrap);
// GL_MAX_TEXTURE_SIZE of the current context (texels per side).
int maxTextureSide();

}  // namespace pgt::gl
