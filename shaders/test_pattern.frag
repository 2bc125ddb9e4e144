#version 450
// Test pattern for tests/vk: checks that fp64 arithmetic really runs in double
// precision and that row 0 of the read-back image is gl_FragCoord.y = 0.5.
//
// For pixel (x, y) and the doubles d[] in the storage buffer:
//   v   = d[(x + 3y) mod n] * (x + 1) + y * 2^-30
//   out = uint(fract(v) * 2^30) + uint(floor(v)) * 2654435761 + salt   (mod 2^32)
// The test keeps every intermediate exactly representable in a double (at
// most 53 significant bits), so rounding mode and FMA contraction cannot
// change the result, while fp32 (24 bits) loses the fractional part.

layout(std430, set = 0, binding = 0) readonly buffer Values {
    double d[];
};

layout(push_constant) uniform Push {
    uint salt;
} push;

layout(location = 0) out uint result;

const double kTwoPow30 = 1073741824.0lf;
const double kTwoPowMinus30 = 9.31322574615478515625e-10lf;

void main() {
    uint x = uint(gl_FragCoord.x);
    uint y = uint(gl_FragCoord.y);
    uint n = uint(d.length());

    precise double v = d[(x + 3u * y) % n] * double(x + 1u) + double(y) * kTwoPowMinus30;
    double whole = floor(v);
    result = uint((v - whole) * kTwoPow30) + uint(whole) * 2654435761u + push.salt;
}
