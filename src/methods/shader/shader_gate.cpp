// The shader gate (methods/shader/shader_gate.h): glslang's syntax tree of the fragment source,
// measured in a child process.
#include "methods/shader/shader_gate.h"

#include <glslang/MachineIndependent/localintermediate.h>
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/memory.h"

namespace pgt::gl {

ShaderBounds shaderBounds() { return {}; }

namespace {
// This process's resident memory in MB (/proc/self/statm), 0 where it cannot be read.
double residentMb() {
    FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f) return 0;
    unsigned long size = 0, resident = 0;
    const bool ok = std::fscanf(f, "%lu %lu", &size, &resident) == 2;
    std::fclose(f);
    return ok ? double(resident) * double(::sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0) : 0;
}
}  // namespace

// The child's own memory beside pgt's stays within the limit (at least 64 MB for the child).
ChildLimits compileLimits() {
    return {30.0, std::max(64.0, double(memoryLimitMb()) - residentMb())};
}

std::string compileFailure(const ChildStatus& st, const ChildLimits& limits) {
    char buf[160];
    switch (st.end) {
        case ChildEnd::TimedOut:
            std::snprintf(buf, sizeof buf, "ran longer than the compile time limit of %.0f s",
                          limits.seconds);
            return buf;
        case ChildEnd::OverMemory:
            std::snprintf(buf, sizeof buf,
                          "needed more than the %.0f MB the memory limit (--memory-limit) left it",
                          limits.memoryMb);
            return buf;
        case ChildEnd::Signalled:
            return "crashed on this file (signal " + std::to_string(st.code) + ")";
        case ChildEnd::Exited:
            break;
    }
    // No answer and an exit status: a crash caught by a handler in the child (AddressSanitizer
    // reports a SEGV and exits 1).
    return "crashed on this file (it ended with exit status " + std::to_string(st.code) +
           " and no answer)";
}

bool writeAll(int fd, const std::string& data) {
    for (size_t off = 0; off < data.size();) {
        const ssize_t n = ::write(fd, data.data() + off, data.size() - off);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        off += size_t(n);
    }
    return true;
}

namespace {

// The tree's measures: its depth (not descending past the bound, so the walk itself stays
// shallow), its nodes, and each function's calls.
class Measure : public glslang::TIntermTraverser {
  public:
    explicit Measure(int depthBound) : bound_(depthBound) {}
    long nodes = 0;
    int deepest = 0;
    std::map<std::string, std::set<std::string>> calls;  // function -> functions it calls

    bool visitBinary(glslang::TVisit, glslang::TIntermBinary*) override { return enter(); }
    bool visitUnary(glslang::TVisit, glslang::TIntermUnary*) override { return enter(); }
    bool visitSelection(glslang::TVisit, glslang::TIntermSelection*) override { return enter(); }
    bool visitLoop(glslang::TVisit, glslang::TIntermLoop*) override { return enter(); }
    bool visitBranch(glslang::TVisit, glslang::TIntermBranch*) override { return enter(); }
    bool visitSwitch(glslang::TVisit, glslang::TIntermSwitch*) override { return enter(); }
    void visitSymbol(glslang::TIntermSymbol*) override { ++nodes; }
    void visitConstantUnion(glslang::TIntermConstantUnion*) override { ++nodes; }
    bool visitAggregate(glslang::TVisit, glslang::TIntermAggregate* node) override {
        if (node->getOp() == glslang::EOpFunction) {
            current_ = node->getName().c_str();
            calls[current_];  // a function that calls none is still one
        }
        if (node->getOp() == glslang::EOpFunctionCall)
            calls[current_].insert(node->getName().c_str());
        return enter();
    }

  private:
    bool enter() {
        ++nodes;
        deepest = std::max(deepest, depth);
        return depth < bound_;
    }
    int bound_;
    std::string current_;
};

// The longest chain of calls from `f` (a function calling none: 1), memoised; a cycle
// (recursion, which GLSL forbids and the GL reports) counts once.
int chain(const std::string& f, const std::map<std::string, std::set<std::string>>& calls,
          std::map<std::string, int>& memo) {
    if (auto it = memo.find(f); it != memo.end()) return it->second;
    memo[f] = 1;  // while visiting: a cycle stops here
    int longest = 1;
    if (auto it = calls.find(f); it != calls.end())
        for (const std::string& g : it->second)
            longest = std::max(longest, 1 + chain(g, calls, memo));
    return memo[f] = longest;
}

// In the child: the measures as one line, "depth nodes functions calldepth".
std::string measureInChild(const std::string& source) {
    static const bool initialised = glslang::InitializeProcess();
    (void)initialised;
    glslang::TShader shader(EShLangFragment);
    const char* strings[] = {source.c_str()};
    const int lengths[] = {int(source.size())};
    shader.setStringsWithLengths(strings, lengths, 1);
    // Plain GLSL as a GL driver reads it (no SPIR-V rules: uniforms need no locations).
    shader.setEnvInput(glslang::EShSourceGlsl, EShLangFragment, glslang::EShClientNone, 0);
    shader.parse(GetDefaultResources(), 450, ECoreProfile, false, false, EShMsgDefault);
    const ShaderBounds b = shaderBounds();
    Measure m(b.expressionDepth + 1);
    TIntermNode* root =
        shader.getIntermediate() ? shader.getIntermediate()->getTreeRoot() : nullptr;
    if (root) root->traverse(&m);
    const long functions = long(m.calls.size());
    int callDepth = 0;  // measured only below the functions' bound, which keeps chain() shallow
    std::map<std::string, int> memo;
    if (functions <= b.functions)
        for (const auto& [f, _] : m.calls) callDepth = std::max(callDepth, chain(f, m.calls, memo));
    std::ostringstream out;
    out << m.deepest << " " << m.nodes << " " << functions << " " << callDepth;
    return out.str();
}

}  // namespace

void checkShaderBounds(const std::string& source, const std::string& file,
                       const std::string& field) {
    std::string answer;
    const ChildLimits limits = compileLimits();
    const ChildStatus st = runInChild(
        [&](int fd) { return writeAll(fd, measureInChild(source)) ? 0 : 1; }, limits, &answer);
    auto refuse = [&](const std::string& why) {
        throw InputError(file, field, "",
                         "refused before the GL compiles it: " + why +
                             " (docs/testing.md, \"What pgt promises\": shader bounds)");
    };
    if (st.end != ChildEnd::Exited || st.code != 0)
        refuse("the shader parser (glslang, in a child process) " + compileFailure(st, limits) +
               ": an expression or a chain of calls nested too deeply, or a macro that "
               "expands without end?");
    int depth = 0, functions = 0, callDepth = 0;
    long nodes = 0;
    std::istringstream in(answer);
    if (!(in >> depth >> nodes >> functions >> callDepth)) refuse("no answer from the parser");
    const ShaderBounds b = shaderBounds();
    if (depth > b.expressionDepth)
        refuse("an expression or statement nested more than " + std::to_string(b.expressionDepth) +
               " levels deep (the bound)");
    auto over = [&](const std::string& what, long value, long bound) {
        if (value > bound)
            refuse(std::to_string(value) + " " + what + " (the bound is " + std::to_string(bound) +
                   ")");
    };
    over("functions defined", functions, b.functions);
    over("functions in a chain of calls", callDepth, b.callDepth);
    over("syntax tree nodes", nodes, b.nodes);
}

}  // namespace pgt::gl
