// Strip-wise first draws and timed passes (methods/shader/timed_draws.h).
#include "methods/shader/timed_draws.h"

#include <algorithm>
#include <chrono>

#include "core/interrupt.h"

namespace pgt {

// The first draw of an image, in strips of rows, each finished before the next: the cancel
// flag (Ctrl-C in Python) is polled between them, so a slow shader on a software GL stops
// within about a strip's time (aimed at 0.05-0.25 s: the strip doubles while it is faster,
// halves while slower) instead of after the whole image's. Strips start on even rows, so no
// 2x2 quad (its derivatives) is split.
double drawInStrips(int w, int h) {
    const auto start = std::chrono::steady_clock::now();
    glEnable(GL_SCISSOR_TEST);
    int rows = 8;
    for (int y = 0; y < h;) {
        const int n = std::min(rows, h - y);
        const auto t0 = std::chrono::steady_clock::now();
        glScissor(0, y, w, n);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glFinish();
        y += n;
        if (cancelRequested()) {
            glDisable(GL_SCISSOR_TEST);
            throw Cancelled();
        }
        const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (s < 0.05 && rows < h)
            rows *= 2;
        else if (s > 0.25 && rows > 2)
            rows /= 2;
    }
    glDisable(GL_SCISSOR_TEST);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// One timed pass over the image (GL time and wall time, ns): one draw, or where a whole draw
// takes longer than a poll may wait (a slow shader on a software GL), strips of rows of about
// 0.1 s each, the cancel flag polled between them; the pass's time is the strips' sum.
std::pair<double, double> timedPass(int w, int h, double wholeSeconds, GLuint query) {
    int rows = h;
    if (wholeSeconds > 0.25) rows = std::max(2, int(h * 0.1 / wholeSeconds) & ~1);
    if (rows < h) glEnable(GL_SCISSOR_TEST);
    double gpu = 0, wall = 0;
    for (int y = 0; y < h; y += rows) {
        if (rows < h) glScissor(0, y, w, std::min(rows, h - y));
        glFinish();
        if (cancelRequested()) {
            glDisable(GL_SCISSOR_TEST);
            throw Cancelled();
        }
        auto t0 = std::chrono::steady_clock::now();
        glBeginQuery(GL_TIME_ELAPSED, query);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glEndQuery(GL_TIME_ELAPSED);
        glFinish();
        wall +=
            std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
        GLuint64 t = 0;
        glGetQueryObjectui64v(query, GL_QUERY_RESULT, &t);
        gpu += double(t);
    }
    glDisable(GL_SCISSOR_TEST);
    return {gpu, wall};
}

}  // namespace pgt
