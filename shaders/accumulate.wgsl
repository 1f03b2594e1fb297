// accumulate.wgsl — per-pixel running sums of the radiance samples, compensated so that the
// mean stays accurate to ~1e-7 relative after millions of samples.
//
// Every sample is added with Kahan summation to both the sum and the sum of squares (for the
// per-pixel variance). Kahan's correction term stays below one ulp of the sum; Neumaier's
// variant lets its error term grow and drift in f32 over 10^6 samples of a constant. The state carries over between frames bit for
// bit, so the result does not depend on how samples were split into dispatches.

// AccumPixel is declared in accum_pixel.wgsl (shared with the display pass).


@group(0) @binding(BINDING_ACCUM) var<storage, read_write> accum: array<AccumPixel>;

// An identity the compiler cannot see through: XOR with a uniform that is always 0. Without it,
// shader compilers may simplify (s - (s + x)) + x to 0 under relaxed float rules (Mesa's NIR
// does), silently turning compensated summation back into plain summation.
fn opaque(v: vec3f) -> vec3f {
    return bitcast<vec3f>(bitcast<vec3u>(v) ^ vec3u(frame.opaque_zero));
}

// Kahan summation: err holds minus the low-order part lost so far; s + x is computed as
// s + (x - err), and the new loss is recovered as (t - s) - y.
fn compensated_add(s: ptr<function, vec3f>, err: ptr<function, vec3f>, x: vec3f) {
    let y = x - *err;
    let t = opaque(*s + y);
    *err = (t - *s) - y;
    *s = t;
}

// Rays traced by this invocation in this dispatch (intersect.wgsl counts them).
var<private> rays_traced: u32;

fn accum_add_rays(p: ptr<function, AccumPixel>, n: u32) {
    let lo = (*p).rays_lo + n;
    (*p).rays_hi += select(0u, 1u, lo < n);
    (*p).rays_lo = lo;
}

fn accum_add_sample(p: ptr<function, AccumPixel>, x: vec3f) {
    var s = (*p).sum;
    var e = (*p).sum_err;
    compensated_add(&s, &e, x);
    (*p).sum = s;
    (*p).sum_err = e;
    var s2 = (*p).sum_sq;
    var e2 = (*p).sum_sq_err;
    compensated_add(&s2, &e2, x * x);
    (*p).sum_sq = s2;
    (*p).sum_sq_err = e2;
    (*p).count += 1u;
}
