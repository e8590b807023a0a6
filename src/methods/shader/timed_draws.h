// The full-screen draws of a GLSL method's image (internal to src/methods/shader/): the first
// draw in strips of rows that grow or shrink toward 0.05-0.25 s each, and timed passes, each
// one draw or, for a shader whose image takes longer than a poll may wait, strips of about
// 0.1 s; the cancel flag (Ctrl-C in Python) is polled between strips.
#pragma once

#include <utility>

#include "methods/shader/gl_api.h"

namespace pgt {

// The first draw of a w x h image; returns its wall time in seconds.
double drawInStrips(int w, int h);

// One timed pass over the image: (GL time, wall time) in ns, summed over its strips.
std::pair<double, double> timedPass(int w, int h, double wholeSeconds, GLuint query);

}  // namespace pgt
