// The process's headless OpenGL context through EGL: the surfaceless Mesa platform, or an
// EGL device (a hardware GPU); the GL error helpers.
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <exception>
#include <future>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "core/error.h"
#include "methods/shader/gl_api.h"

namespace pgt {

namespace gl {
std::mutex gMutex;
}  // namespace gl

using gl::gMutex;

namespace {

std::string gDevice;
bool gTried = false;
std::exception_ptr gFailurePtr;  // why the context could not be made (rethrown each use)
GlInfo gInfo;
EGLDisplay gDisplay = EGL_NO_DISPLAY;
EGLContext gContext = EGL_NO_CONTEXT;

std::string eglErrorString() {
    std::ostringstream os;
    os << "EGL error 0x" << std::hex << eglGetError();
    return os.str();
}

// "egl-device:N" -> N; a malformed value is bad input naming the option.
int deviceIndex(const std::string& device) {
    const std::string prefix = "egl-device:";
    const std::string digits = device.rfind(prefix, 0) == 0 ? device.substr(prefix.size()) : "";
    if (digits.empty() || digits.size() > 3 ||
        digits.find_first_not_of("0123456789") != std::string::npos)
        throw InputError("command line", "--gl-device", device,
                         "expected egl-device:N (N from 0), or no option for EGL surfaceless");
    return std::stoi(digits);
}

EGLDisplay openDisplay(const std::string& device) {
    if (device.empty())
        return eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    const int index = deviceIndex(device);
    auto query =
        reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    if (!query)
        throw std::runtime_error("EGL has no eglQueryDevicesEXT (EGL_EXT_device_enumeration)");
    EGLDeviceEXT devices[16];
    EGLint n = 0;
    if (!query(16, devices, &n) || index < 0 || index >= n)
        throw InputError("command line", "--gl-device", device,
                         "EGL lists " + std::to_string(n) + " device(s) on this machine");
    return eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[index], nullptr);
}

void createContext() {
    gTried = true;
    EGLDisplay dpy = openDisplay(gDevice);
    if (dpy == EGL_NO_DISPLAY) throw std::runtime_error("no EGL display: " + eglErrorString());
    EGLint major = 0, minor = 0;
    if (!eglInitialize(dpy, &major, &minor))
        throw std::runtime_error("eglInitialize failed: " + eglErrorString() +
                                 " (is Mesa's EGL installed? libegl-mesa0, libgl1-mesa-dri)");
    if (!eglBindAPI(EGL_OPENGL_API)) throw std::runtime_error("eglBindAPI(OpenGL) failed");
    const EGLint configAttribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                    EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config;
    EGLint count = 0;
    if (!eglChooseConfig(dpy, configAttribs, &config, 1, &count) || count < 1)
        throw std::runtime_error("no EGL config for desktop OpenGL: " + eglErrorString());
    const EGLint ctxAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                 4,
                                 EGL_CONTEXT_MINOR_VERSION,
                                 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, ctxAttribs);
    if (ctx == EGL_NO_CONTEXT)
        throw std::runtime_error("cannot create an OpenGL 4.5 core context: " + eglErrorString());
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx))
        throw std::runtime_error("eglMakeCurrent without a surface failed: " + eglErrorString());
    gDisplay = dpy;
    gContext = ctx;
    auto str = [](GLenum e) {
        const GLubyte* s = glGetString(e);
        return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
    };
    gInfo.renderer = str(GL_RENDERER);
    gInfo.version = str(GL_VERSION);
    gInfo.vendor = str(GL_VENDOR);
    int glslMajor = 0, glslMinor = 0;  // "4.50 ..." (the desktop form: a 4.5 core context)
    if (std::sscanf(str(GL_SHADING_LANGUAGE_VERSION).c_str(), "%d.%d", &glslMajor, &glslMinor) == 2)
        gInfo.glslVersion = glslMajor * 100 + glslMinor;
    for (const char* sw : {"llvmpipe", "softpipe", "swrast", "SwiftShader"})
        if (gInfo.renderer.find(sw) != std::string::npos) gInfo.software = true;
}

}  // namespace

namespace gl {

void ensureContext() {
    if (!gTried) {
        try {
            createContext();
        } catch (const InputError&) {
            gFailurePtr = std::current_exception();
        } catch (const std::exception& e) {
            gFailurePtr = std::make_exception_ptr(
                std::runtime_error(std::string("OpenGL unavailable: ") + e.what()));
        }
    }
    if (gFailurePtr) std::rethrow_exception(gFailurePtr);
    if (eglGetCurrentContext() != gContext)
        eglMakeCurrent(gDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, gContext);
}

namespace {

// The GL thread: a queue of jobs, each run to its end before the next. Started on first use
// and never stopped (the context lives as long as the process, as before).
class GlThread {
  public:
    GlThread() : thread_([this] { loop(); }) { thread_.detach(); }
    bool isThisThread() const { return std::this_thread::get_id() == id_.load(); }
    void run(const std::function<void()>& job) {
        std::packaged_task<void()> task(job);
        std::future<void> done = task.get_future();
        {
            std::lock_guard<std::mutex> lock(mutex_);
            queue_.push_back(std::move(task));
        }
        wake_.notify_one();
        done.get();  // rethrows the job's exception
    }

  private:
    void loop() {
        id_ = std::this_thread::get_id();
        for (;;) {
            std::packaged_task<void()> task;
            {
                std::unique_lock<std::mutex> lock(mutex_);
                wake_.wait(lock, [this] { return !queue_.empty(); });
                task = std::move(queue_.front());
                queue_.pop_front();
            }
            task();
        }
    }
    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::packaged_task<void()>> queue_;
    std::atomic<std::thread::id> id_{};
    std::thread thread_;
};

}  // namespace

void onGlThread(const std::function<void()>& job) {
    static GlThread* const thread = new GlThread;  // never destroyed: detached, like the context
    if (thread->isThisThread()) return job();
    thread->run(job);
}

const GlInfo& contextInfo() { return gInfo; }

void checkGl(const std::string& what) {
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        std::ostringstream os;
        os << "OpenGL error 0x" << std::hex << e << " in " << what;
        throw std::runtime_error(os.str());
    }
}

// GL_MAX_TEXTURE_SIZE of the current context (texels per side).
int maxTextureSide() {
    GLint side = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &side);
    return int(side);
}

// Any GL error left by an earlier call is reported there; start each step clean so that a
// later check blames only its own calls.
void drainGlErrors() {
    for (int k = 0; k < 16 && glGetError() != GL_NO_ERROR; ++k) {
    }
}

}  // namespace gl

void setGlDevice(const std::string& device) {
    if (!device.empty()) deviceIndex(device);  // the form now; the device at first use
    std::lock_guard<std::mutex> lock(gMutex);
    if (gTried && device != gDevice)
        throw std::runtime_error("the GL device is chosen before the first GL method runs");
    gDevice = device;
}

std::optional<GlInfo> glContextIfMade() {
    std::lock_guard<std::mutex> lock(gMutex);
    if (!gTried || gInfo.renderer.empty()) return std::nullopt;
    return gInfo;
}

const GlInfo& glContext(const std::string& device) {
    {
        std::lock_guard<std::mutex> lock(gMutex);
        if (!device.empty() && !gTried) gDevice = device;
    }
    gl::onGlThread([] {
        std::lock_guard<std::mutex> lock(gMutex);
        gl::ensureContext();
    });
    return gInfo;
}

}  // namespace pgt
