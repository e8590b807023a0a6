// pgt built-in "maxmip" as GLSL (src/methods/builtin/maxmip.h; Tevs, Ihrke, Seidel, "Maximum
// Mipmaps", I3D 2008): exact tracing over the minimum-maximum pyramid, the cell's bilinear
// patch met as a quadratic along the ray, for any (s, b) and either address mode.
// Samplers: heightMap (the map, read texel by texel with texelFetch) and pyramidMap (the
// pyramid as pgt uploads it: RG32F, level k in rows pgt_pyramid_row[k] onward, (lo, hi) per
// node). pgt sets pgt_pyramid_row, pgt_pyramid_top, pgt_map_size and pgt_map_repeat.
// Uniforms: height_scale, height_bias (floats), max_iterations (int).
uniform sampler2D heightMap;
uniform sampler2D pyramidMap;
uniform float height_scale;
uniform float height_bias;
uniform int max_iterations;
uniform int pgt_pyramid_row[32];
uniform int pgt_pyramid_top;
uniform ivec2 pgt_map_size;
uniform int pgt_map_repeat;

// The texels lattice corners [x0, x0 + n] map to on one axis of `size` texels: one or two
// inclusive ranges (a, b) in xy and zw; returns how many.
int pgtMapRange(int x0, int n, int size, out ivec4 r) {
    r = ivec4(0);
    if (pgt_map_repeat == 0) {
        r.xy = ivec2(clamp(x0, 0, size - 1), clamp(x0 + n, 0, size - 1));
        return 1;
    }
    if (n + 1 >= size) {
        r.xy = ivec2(0, size - 1);
        return 1;
    }
    int a = x0 % size;
    if (a < 0) a += size;
    int b = a + n;
    if (b <= size - 1) {
        r.xy = ivec2(a, b);
        return 1;
    }
    r = ivec4(a, size - 1, 0, b - size);
    return 2;
}

// (lo, hi) of the height over lattice cells [x0, x0 + n) x [y0, y0 + n), as latticeBounds.
vec2 pgtBounds(int x0, int y0, int n) {
    ivec4 xs, ys;
    int nx = pgtMapRange(x0, n, pgt_map_size.x, xs);
    int ny = pgtMapRange(y0, n, pgt_map_size.y, ys);
    vec2 bound = vec2(1e30, -1e30);
    for (int a = 0; a < nx; ++a) {
        ivec2 xr = a == 0 ? xs.xy : xs.zw;
        for (int c = 0; c < ny; ++c) {
            ivec2 yr = c == 0 ? ys.xy : ys.zw;
            int span = max(xr.y - xr.x, yr.y - yr.x);
            int k = 0;
            while (k < pgt_pyramid_top && (1 << k) < span) ++k;
            int size = 1 << k;
            int lw = ((pgt_map_size.x - 1) >> k) + 1, lh = ((pgt_map_size.y - 1) >> k) + 1;
            int i0 = xr.x >> k, j0 = yr.x >> k;
            int i1 = xr.y <= i0 * size + size ? i0 : i0 + 1;
            int j1 = yr.y <= j0 * size + size ? j0 : j0 + 1;
            for (int j = j0; j <= min(j1, lh - 1); ++j)
                for (int i = i0; i <= min(i1, lw - 1); ++i) {
                    vec2 node = texelFetch(pyramidMap, ivec2(i, pgt_pyramid_row[k] + j), 0).rg;
                    bound = vec2(min(bound.x, node.x), max(bound.y, node.y));
                }
        }
    }
    return bound;
}

int pgtAddress(int i, int size) {
    if (pgt_map_repeat == 0) return clamp(i, 0, size - 1);
    int m = i % size;
    return m < 0 ? m + size : m;
}

// The smallest sigma in [0, sigma1] with C + B sigma + A sigma^2 <= 0, as maxmip::firstRoot.
bool pgtFirstRoot(float A, float B, float C, float sigma1, out float sigma) {
    sigma = 0.0;
    if (!(C > 0.0)) return true;
    float best = 1e30;
    if (A == 0.0) {
        if (B < 0.0) {
            float r = -C / B;
            if (r >= 0.0 && r <= sigma1) best = r;
        }
    } else {
        float disc = B * B - 4.0 * A * C;
        if (disc >= 0.0) {
            float sq = sqrt(disc);
            float q = -0.5 * (B + (B >= 0.0 ? sq : -sq));
            float r1 = q / A;
            if (r1 >= 0.0 && r1 <= sigma1 && r1 < best) best = r1;
            if (q != 0.0) {
                float r2 = C / q;
                if (r2 >= 0.0 && r2 <= sigma1 && r2 < best) best = r2;
            }
        }
    }
    if (best <= sigma1) {
        sigma = best;
        return true;
    }
    if (!(C + (B + A * sigma1) * sigma1 <= 0.0)) return false;
    float lo = 0.0, hi = sigma1;
    for (int k = 0; k < 64 && lo < hi; ++k) {
        float mid = lo + (hi - lo) * 0.5;
        if (mid <= lo || mid >= hi) break;
        if (C + (B + A * mid) * mid > 0.0)
            lo = mid;
        else
            hi = mid;
    }
    sigma = hi;
    return true;
}

vec2 MaxMipTrace(vec2 uv0, vec3 V) {
    float s = height_scale, b = height_bias;
    vec2 dir = V.xy / V.z;
    if (!(V.z > 0.0)) return vec2(uintBitsToFloat(0x7fc00000u));
    vec2 whole = texelFetch(pyramidMap, ivec2(0, pgt_pyramid_row[pgt_pyramid_top]), 0).rg;
    float zTop = s >= 0.0 ? s * whole.y + b : s * whole.x + b;
    float zBot = s >= 0.0 ? s * whole.x + b : s * whole.y + b;
    float W = float(pgt_map_size.x), H = float(pgt_map_size.y);
    vec2 start = uv0 + dir * zTop;
    float X0 = start.x * W - 0.5, Y0 = start.y * H - 0.5;
    float dX = -dir.x * W, dY = -dir.y * H;
    float tauMax = zTop - zBot;
    if (!(abs(X0) < 1073741824.0 && abs(Y0) < 1073741824.0)) return uv0 + dir * (zTop - tauMax);
    int level = pgt_pyramid_top;
    int nx = int(floor(X0)) >> level, ny = int(floor(Y0)) >> level;
    float tau = 0.0;
    for (int iteration = 0;; ++iteration) {
        if (iteration == max_iterations) return uv0 + dir * (zTop - tau);
        int size = 1 << level;
        float tx = dX > 0.0 ? (float((nx + 1) * size) - X0) / dX
                 : dX < 0.0 ? (float(nx * size) - X0) / dX : 1e30;
        float ty = dY > 0.0 ? (float((ny + 1) * size) - Y0) / dY
                 : dY < 0.0 ? (float(ny * size) - Y0) / dY : 1e30;
        float tExit = min(tx, ty);
        vec2 bound = pgtBounds(nx * size, ny * size, size);
        float zMax = s >= 0.0 ? s * bound.y + b : s * bound.x + b;
        float tEnter = max(tau, zTop - zMax);
        if (tEnter < tExit) {
            if (level > 0) {
                tau = tEnter;
                --level;
                float x = X0 + dX * tau, y = Y0 + dY * tau;
                int halfSize = 1 << level;
                float mx = float((2 * nx + 1) * halfSize), my = float((2 * ny + 1) * halfSize);
                nx = 2 * nx + ((x > mx || (x == mx && dX > 0.0)) ? 1 : 0);
                ny = 2 * ny + ((y > my || (y == my && dY > 0.0)) ? 1 : 0);
                continue;
            }
            int i0 = pgtAddress(nx, pgt_map_size.x), i1 = pgtAddress(nx + 1, pgt_map_size.x);
            int j0 = pgtAddress(ny, pgt_map_size.y), j1 = pgtAddress(ny + 1, pgt_map_size.y);
            float h00 = texelFetch(heightMap, ivec2(i0, j0), 0).r;
            float h10 = texelFetch(heightMap, ivec2(i1, j0), 0).r;
            float h01 = texelFetch(heightMap, ivec2(i0, j1), 0).r;
            float h11 = texelFetch(heightMap, ivec2(i1, j1), 0).r;
            float ax = X0 + dX * tEnter - float(nx), ay = Y0 + dY * tEnter - float(ny);
            float e = h10 - h00, f = h01 - h00, g = h00 - h10 - h01 + h11;
            float h0 = h00 + e * ax + f * ay + g * ax * ay;
            float h1 = e * dX + f * dY + g * (ax * dY + ay * dX);
            float h2 = g * dX * dY;
            float sigma1 = min(tExit, tauMax) - tEnter;
            float sigma;
            if (pgtFirstRoot(-s * h2, -1.0 - s * h1, zTop - tEnter - b - s * h0,
                             max(sigma1, 0.0), sigma))
                return uv0 + dir * (zTop - (tEnter + sigma));
        }
        if (tExit >= tauMax) return uv0 + dir * (zTop - tauMax);
        tau = max(tau, tExit);
        int px = nx >> 1, py = ny >> 1;
        if (tx <= ty) nx += dX > 0.0 ? 1 : -1;
        if (ty <= tx) ny += dY > 0.0 ? 1 : -1;
        if (level < pgt_pyramid_top && ((nx >> 1) != px || (ny >> 1) != py)) {
            ++level;
            nx = nx >> 1;
            ny = ny >> 1;
        }
    }
    return uv0;
}
