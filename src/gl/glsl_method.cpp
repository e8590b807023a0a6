// Headless OpenGL through EGL (surfaceless Mesa platform, or an EGL device), the GLSL
// wrapper around a user's parallax function, and the run over a fragment list.
#include "gl/glsl_method.h"

#define EGL_EGLEXT_PROTOTYPES
#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstring>
#include <exception>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "core/error.h"

namespace pgt {

namespace {

std::mutex gMutex;
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
    for (const char* sw : {"llvmpipe", "softpipe", "swrast", "SwiftShader"})
        if (gInfo.renderer.find(sw) != std::string::npos) gInfo.software = true;
}

// Makes the context current on this thread (the caller holds gMutex).
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

// The wrapper: a prelude that counts texture() calls, the user's file (its #version line
// blanked, so its lines keep their numbers), and a main() that feeds the function one
// fragment per output pixel.
constexpr const char* kPrelude = R"(#version 450 core
int pgt_fetches = 0;
vec4 pgt_texture(sampler2D s, vec2 p) { pgt_fetches++; return texture(s, p); }
vec4 pgt_texture(sampler2D s, vec2 p, float b) { pgt_fetches++; return texture(s, p, b); }
vec4 pgt_textureLod(sampler2D s, vec2 p, float l) { pgt_fetches++; return textureLod(s, p, l); }
vec4 pgt_textureGrad(sampler2D s, vec2 p, vec2 dx, vec2 dy) {
    pgt_fetches++; return textureGrad(s, p, dx, dy); }
#define texture pgt_texture
#define textureLod pgt_textureLod
#define textureGrad pgt_textureGrad
)";

constexpr const char* kMain = R"(
uniform sampler2D pgt_uv0;   // RG32F: uv0 of fragment k at texel (k % w, k / w)
uniform sampler2D pgt_view;  // RGBA32F: tangent-space V
uniform int pgt_count;
uniform int pgt_width;
layout(location = 0) out vec2 pgt_out_uv;
layout(location = 1) out float pgt_out_fetches;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    if (p.y * pgt_width + p.x >= pgt_count) discard;
    vec2 uv0 = texelFetch(pgt_uv0, p, 0).xy;
    vec3 v = texelFetch(pgt_view, p, 0).xyz;
    pgt_fetches = 0;
    pgt_out_uv = PGT_FUNCTION(uv0, v);
    pgt_out_fetches = float(pgt_fetches);
}
)";

constexpr const char* kVertex = R"(#version 450 core
void main() {  // one triangle covering the viewport
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

std::string stripVersion(const std::string& src) {
    std::istringstream in(src);
    std::ostringstream out;
    std::string line;
    while (std::getline(in, line)) {
        size_t first = line.find_first_not_of(" \t");
        if (first != std::string::npos && line.compare(first, 8, "#version") == 0) line.clear();
        out << line << "\n";
    }
    return out.str();
}

// Driver messages "S:L(C): error: ..." (Mesa) or "S(L) : error ..." with L a line of the
// whole fragment shader: lines (first, first + count] are the user's file (Mesa does not
// keep #line's source numbers on every message, so lines are mapped by position).
std::string translateLog(const std::string& log, const std::string& file, int first, int count) {
    std::istringstream in(log);
    std::ostringstream out;
    std::string line;
    auto digitsAt = [](const std::string& t, size_t& i) {
        size_t start = i;
        while (i < t.size() && t[i] >= '0' && t[i] <= '9') ++i;
        return t.substr(start, i - start);
    };
    while (std::getline(in, line)) {
        size_t i = 0;
        std::string src = digitsAt(line, i), ln, col;
        (void)src;
        bool ok = !src.empty() && i < line.size();
        if (ok && line[i] == ':') {  // Mesa: S:L(C): rest
            ++i;
            ln = digitsAt(line, i);
            ok = !ln.empty() && i < line.size() && line[i] == '(';
            if (ok) {
                ++i;
                col = digitsAt(line, i);
                ok = i + 2 < line.size() && line.compare(i, 3, "): ") == 0;
                i += 3;
            }
        } else if (ok && line[i] == '(') {  // S(L) : rest
            ++i;
            ln = digitsAt(line, i);
            ok = !ln.empty() && line.compare(i, 1, ")") == 0;
            ++i;
            while (ok && i < line.size() && (line[i] == ' ' || line[i] == ':')) ++i;
        } else {
            ok = false;
        }
        if (!ok) {
            if (!line.empty()) out << line << "\n";
            continue;
        }
        int n = std::stoi(ln);
        std::string where = n <= first ? "pgt prelude" : n <= first + count ? file : "pgt wrapper";
        if (n > first && n <= first + count) n -= first;
        out << where << ":" << n << (col.empty() ? "" : ":" + col) << ": " << line.substr(i)
            << "\n";
    }
    return out.str();
}

bool isIdentifier(const std::string& s) {
    if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
    for (char c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
    return true;
}

int countLines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

// A shader's or program's info log (glGet{Shader,Program}iv + ...InfoLog).
template <class GetIv, class GetLog>
std::string infoLog(GLuint object, GetIv getIv, GetLog getLog) {
    GLint len = 0;
    getIv(object, GL_INFO_LOG_LENGTH, &len);
    std::string log(size_t(std::max(len, 1)), '\0');
    getLog(object, len, nullptr, log.data());
    return log.c_str();  // up to the terminating NUL
}

// `userFirst`, `userCount`: where the user's file sits in `src` (for the messages).
GLuint compile(GLenum type, const std::string& src, const std::string& file, int userFirst = 0,
               int userCount = 1 << 30) {
    GLuint s = glCreateShader(type);
    const char* p = src.c_str();
    glShaderSource(s, 1, &p, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        std::string log = infoLog(s, glGetShaderiv, glGetShaderInfoLog);
        glDeleteShader(s);
        throw InputError(
            file, "glsl", "",
            "the shader does not compile:\n" + translateLog(log, file, userFirst, userCount));
    }
    return s;
}

struct Program {
    GLuint id = 0;
};

// Programs by (file, source, function): compiled once per process.
std::map<std::string, Program> gPrograms;
GLuint gVao = 0;

GLuint programFor(const GlslSpec& spec) {
    std::string key = spec.path + "\n" + spec.function + "\n" + spec.source;
    auto it = gPrograms.find(key);
    if (it != gPrograms.end()) return it->second.id;
    if (!isIdentifier(spec.function))
        throw InputError(spec.path, "function", spec.function, "is not a GLSL identifier");
    const std::string user = stripVersion(spec.source);
    const int first = countLines(kPrelude), count = countLines(user);
    std::string fs =
        std::string(kPrelude) + user + "#define PGT_FUNCTION " + spec.function + "\n" + kMain;
    GLuint vs = compile(GL_VERTEX_SHADER, kVertex, "pgt vertex shader");
    GLuint f = compile(GL_FRAGMENT_SHADER, fs, spec.path, first, count);
    GLuint prog = glCreateProgram();
    glAttachShader(prog, vs);
    glAttachShader(prog, f);
    glLinkProgram(prog);
    glDeleteShader(vs);
    glDeleteShader(f);
    GLint ok = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        std::string log = infoLog(prog, glGetProgramiv, glGetProgramInfoLog);
        glDeleteProgram(prog);
        throw InputError(
            spec.path, "glsl", "",
            "the shader does not link:\n" + translateLog(log, spec.path, first, count));
    }
    gPrograms[key] = {prog};
    return prog;
}

GLuint makeTexture(GLenum internal, GLenum format, int w, int h, const void* data, GLenum filter,
                   GLenum wrap) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, GLint(internal), w, h, 0, format, GL_FLOAT, data);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GLint(filter));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GLint(filter));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GLint(wrap));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GLint(wrap));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    return t;
}

// Map textures (height or depth R32F, 003's RGB normal map, the parallax map): one upload per
// content (keyed by a hash of the texels, never by address), bilinear, the map's address mode
// (MODEL.md §1: texel centres at (i + 0.5) / W, as GL samples).
std::map<std::tuple<uint64_t, int, int, int, bool, int>, GLuint> gMaps;

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

GLuint mapTexture(const Texture& t, bool depth) {
    uint64_t hash = 1469598103934665603ull;  // FNV-1a over the texel bits
    for (float x : t.texels) {
        uint32_t bits;
        std::memcpy(&bits, &x, 4);
        hash = (hash ^ bits) * 1099511628211ull;
    }
    auto key = std::make_tuple(hash, t.width, t.height, t.channels, depth, int(t.address));
    auto it = gMaps.find(key);
    if (it != gMaps.end()) return it->second;
    const int c = t.channels >= 3 ? 3 : 1;
    std::vector<float> data(size_t(t.width) * t.height * size_t(c));
    for (size_t k = 0; k < size_t(t.width) * t.height; ++k)
        for (int ch = 0; ch < c; ++ch) {
            float h = t.texels[k * size_t(t.channels) + size_t(ch)];
            data[k * size_t(c) + size_t(ch)] = depth ? 1.0f - h : h;
        }
    GLuint id = makeTexture(c == 3 ? GL_RGB32F : GL_R32F, c == 3 ? GL_RGB : GL_RED, t.width,
                            t.height, data.data(), GL_LINEAR,
                            t.address == Address::Repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE);
    gMaps[key] = id;
    return id;
}

// A map the GL cannot hold is bad input, named before any upload, not a GL error that a
// later call would report.
void checkMapFits(const GlslSpec& spec, const std::string& field, const std::string& name,
                  const Texture* t) {
    if (name.empty() || !t) return;
    const int maxSide = maxTextureSide();
    if (t->width > maxSide || t->height > maxSide)
        throw InputError(spec.path, field, name,
                         "the map it samples is " + std::to_string(t->width) + "x" +
                             std::to_string(t->height) +
                             " texels, more than this GL's "
                             "GL_MAX_TEXTURE_SIZE " +
                             std::to_string(maxSide) + " (" + gInfo.renderer +
                             "); use a smaller height map or no GLSL method");
}

void bindSampler(GLuint prog, const GlslSpec& spec, const std::string& field,
                 const std::string& name, int unit, const Texture* t, bool depth) {
    if (name.empty()) return;
    GLint loc = glGetUniformLocation(prog, name.c_str());
    if (loc < 0)
        throw InputError(spec.path, field, name,
                         "is not an active sampler2D uniform of the shader (declare it and "
                         "sample it in " +
                             spec.function + ")");
    PGT_CHECK(t != nullptr);
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    glBindTexture(GL_TEXTURE_2D, mapTexture(*t, depth));
    glUniform1i(loc, unit);
    checkGl("uploading the map of " + field + " " + name);
}

}  // namespace

void setGlDevice(const std::string& device) {
    if (!device.empty()) deviceIndex(device);  // the form now; the device at first use
    std::lock_guard<std::mutex> lock(gMutex);
    if (gTried && device != gDevice)
        throw std::runtime_error("the GL device is chosen before the first GL method runs");
    gDevice = device;
}

const GlInfo& glContext(const std::string& device) {
    std::lock_guard<std::mutex> lock(gMutex);
    if (!device.empty() && !gTried) gDevice = device;
    ensureContext();
    return gInfo;
}

namespace {

// One draw over at most kChunkFragments fragments (runGlsl splits longer lists).
GlslRun runGlslChunk(const GlslSpec& spec, const Texture& height, const Texture* normal,
                     const Texture* parallax, double scale, double bias,
                     const std::vector<Vec2f>& uv0, const std::vector<Vec3f>& view,
                     int timingRepeats) {
    GlslRun run;
    const int n = int(uv0.size());
    if (n == 0) return run;
    GLuint prog = programFor(spec);
    glUseProgram(prog);
    if (!gVao) glGenVertexArrays(1, &gVao);
    glBindVertexArray(gVao);

    // Fragment k at texel (k % w, k / w) of the input and output images.
    const int w = std::min(n, 2048), h = (n + w - 1) / w;
    std::vector<float> uvData(size_t(w) * h * 2, 0.0f), viewData(size_t(w) * h * 4, 0.0f);
    for (int k = 0; k < n; ++k) {
        uvData[2 * size_t(k)] = uv0[size_t(k)].x;
        uvData[2 * size_t(k) + 1] = uv0[size_t(k)].y;
        viewData[4 * size_t(k)] = view[size_t(k)].x;
        viewData[4 * size_t(k) + 1] = view[size_t(k)].y;
        viewData[4 * size_t(k) + 2] = view[size_t(k)].z;
    }
    GLuint uvTex = makeTexture(GL_RG32F, GL_RG, w, h, uvData.data(), GL_NEAREST, GL_CLAMP_TO_EDGE);
    GLuint viewTex =
        makeTexture(GL_RGBA32F, GL_RGBA, w, h, viewData.data(), GL_NEAREST, GL_CLAMP_TO_EDGE);
    GLuint outUv = makeTexture(GL_RG32F, GL_RG, w, h, nullptr, GL_NEAREST, GL_CLAMP_TO_EDGE);
    GLuint outFetch = makeTexture(GL_R32F, GL_RED, w, h, nullptr, GL_NEAREST, GL_CLAMP_TO_EDGE);
    GLuint fbo = 0;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, outUv, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, outFetch, 0);
    const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, bufs);
    PGT_CHECK(glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE);

    // Units: 0 = the height/depth map, 1 = uv0, 2 = V, 3 = normal map, 4 = parallax map.
    bindSampler(prog, spec, "sampler", spec.sampler, 0, &height, spec.depthTexture);
    bindSampler(prog, spec, "normal_sampler", spec.normalSampler, 3, normal, false);
    bindSampler(prog, spec, "parallax_sampler", spec.parallaxSampler, 4, parallax, false);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, uvTex);
    glUniform1i(glGetUniformLocation(prog, "pgt_uv0"), 1);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, viewTex);
    glUniform1i(glGetUniformLocation(prog, "pgt_view"), 2);
    glUniform1i(glGetUniformLocation(prog, "pgt_count"), n);
    glUniform1i(glGetUniformLocation(prog, "pgt_width"), w);
    for (const GlslSpec::Uniform& un : spec.uniforms) {
        GLint u = glGetUniformLocation(prog, un.name.c_str());
        if (u < 0)
            throw InputError(spec.path, "uniforms." + un.name, "",
                             "is not an active uniform of the shader (misspelt, or unused by " +
                                 spec.function + ")");
        std::vector<float> f(un.values.begin(), un.values.end());
        drainGlErrors();  // only this uniform's own error may be blamed on it
        if (un.bind == "scale") f = {float(scale)};
        if (un.bind == "bias") f = {float(bias)};
        if (un.isInt)
            glUniform1i(u, int(un.values[0]));
        else if (f.size() == 1)
            glUniform1f(u, f[0]);
        else if (f.size() == 2)
            glUniform2f(u, f[0], f[1]);
        else if (f.size() == 3)
            glUniform3f(u, f[0], f[1], f[2]);
        else
            glUniform4f(u, f[0], f[1], f[2], f[3]);
        if (glGetError() != GL_NO_ERROR)
            throw InputError(spec.path, "uniforms." + un.name, "",
                             "does not match the uniform's type in the shader");
    }
    glViewport(0, 0, w, h);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    const float clear[4] = {NAN, NAN, 0, 0};
    glClearBufferfv(GL_COLOR, 0, clear);
    glClearBufferfv(GL_COLOR, 1, clear + 2);
    // The draw, `timingRepeats` times when timed (each between two glFinish and inside a
    // GL_TIME_ELAPSED query; every draw writes the same outputs), once otherwise.
    GLuint query = 0;
    if (timingRepeats > 0) glGenQueries(1, &query);
    std::vector<double> gpuNs, wallNs;
    for (int r = 0; r < std::max(1, timingRepeats); ++r) {
        if (query) glFinish();
        auto t0 = std::chrono::steady_clock::now();
        if (query) glBeginQuery(GL_TIME_ELAPSED, query);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        if (!query) break;
        glEndQuery(GL_TIME_ELAPSED);
        glFinish();
        wallNs.push_back(
            std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0)
                .count() /
            n);
        GLuint64 t = 0;
        glGetQueryObjectui64v(query, GL_QUERY_RESULT, &t);
        gpuNs.push_back(double(t) / n);
    }
    if (query) {
        glDeleteQueries(1, &query);
        std::sort(gpuNs.begin(), gpuNs.end());
        std::sort(wallNs.begin(), wallNs.end());
        run.gpuNsPerPixel = gpuNs[gpuNs.size() / 2];
        run.wallNsPerPixel = wallNs[wallNs.size() / 2];
    }
    checkGl("the draw of " + spec.path);

    std::vector<float> outUvData(size_t(w) * h * 2), outFetchData(size_t(w) * h);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, w, h, GL_RG, GL_FLOAT, outUvData.data());
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, w, h, GL_RED, GL_FLOAT, outFetchData.data());
    checkGl("reading back " + spec.path);
    run.uv.resize(size_t(n));
    run.fetches.resize(size_t(n));
    for (int k = 0; k < n; ++k) {
        run.uv[size_t(k)] = Vec2f(outUvData[2 * size_t(k)], outUvData[2 * size_t(k) + 1]);
        run.fetches[size_t(k)] = uint32_t(std::max(0.0f, outFetchData[size_t(k)]));
    }

    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    GLuint textures[4] = {uvTex, viewTex, outUv, outFetch};
    glDeleteTextures(4, textures);
    checkGl("cleaning up after " + spec.path);
    return run;
}

// Fragments per draw: the input and output images are 2048 wide, so this keeps them at most
// 2048 x 4096, within the 8192-texel minimum that GL 4.3 guarantees for GL_MAX_TEXTURE_SIZE.
constexpr size_t kChunkFragments = size_t(2048) * 4096;

}  // namespace

GlslRun runGlsl(const GlslSpec& spec, const Texture& height, const Texture* normal,
                const Texture* parallax, double scale, double bias, const std::vector<Vec2f>& uv0,
                const std::vector<Vec3f>& view, int timingRepeats) {
    PGT_CHECK_EQ(uv0.size(), view.size());
    std::lock_guard<std::mutex> lock(gMutex);
    ensureContext();
    drainGlErrors();
    checkMapFits(spec, "sampler", spec.sampler, &height);
    checkMapFits(spec, "normal_sampler", spec.normalSampler, normal);
    checkMapFits(spec, "parallax_sampler", spec.parallaxSampler, parallax);
    if (uv0.size() <= kChunkFragments)
        return runGlslChunk(spec, height, normal, parallax, scale, bias, uv0, view, timingRepeats);
    GlslRun run;  // a long list: draw by chunks; times are the fragment-weighted mean
    for (size_t first = 0; first < uv0.size(); first += kChunkFragments) {
        size_t last = std::min(uv0.size(), first + kChunkFragments);
        std::vector<Vec2f> u(uv0.begin() + long(first), uv0.begin() + long(last));
        std::vector<Vec3f> v(view.begin() + long(first), view.begin() + long(last));
        GlslRun part =
            runGlslChunk(spec, height, normal, parallax, scale, bias, u, v, timingRepeats);
        double weight = double(last - first) / double(uv0.size());
        run.gpuNsPerPixel += part.gpuNsPerPixel * weight;
        run.wallNsPerPixel += part.wallNsPerPixel * weight;
        run.uv.insert(run.uv.end(), part.uv.begin(), part.uv.end());
        run.fetches.insert(run.fetches.end(), part.fetches.begin(), part.fetches.end());
    }
    return run;
}

}  // namespace pgt
