/* The C example firmware: the Rust example firmware's workload (examples/firmware.rs) in
 * C through the C API. It renders the same deterministic 320x240 RGB565 scene
 * (firmware/src/scene.rs, integer only), runs the RBPF and then the colour PF, 100
 * particles each, over its 60 frames in one tracker placed in a static, and prints the
 * checksum over every estimate (firmware/src/run.rs's: 64-bit FNV-1a over each
 * estimate's centre, half-axes, velocity and confidence, Q16.16 bits, and status, as
 * little-endian 32-bit words), which must equal the one the Rust firmware prints.
 * Built with CF_FIRMWARE defined, it is the correlation-filter firmware's workload
 * (examples/cf_firmware.rs) instead: the correlation-filter tracker at its defaults over
 * the same frames, and its checksum, `cf checksum`.
 *
 * Build and run: ffi/c/build.sh firmware, ffi/c/build.sh cf-firmware (docs/c.md). */
#include <stddef.h>
#include <stdint.h>

#include "rbtrack.h"
#include "semihosting.h"
#include "startup.h"

enum {
    WIDTH = 320,
    HEIGHT = 240,
    FRAME_BYTES = WIDTH * HEIGHT * 2,
    FRAMES = 60,            /* frame 0 starts the trackers, 1..=60 are tracked */
    SEED = 1,               /* the scene's seed */
    TRACKER_SEED = 1,       /* the trackers' seed */
    HORIZON_Y = 12,         /* px: the target's half-height is 0 there */
    SCALE_PER_ROW = 1 << 14, /* Q16.16: 0.25 px of half-height per px down */
    GRID_LOG2 = 5,          /* floor colour grid, 32 px */
    TEXTURE = 12,           /* fine floor texture, grey levels each side */
    NOISE = 6,              /* camera noise, grey levels each side */
};
static const int32_t START[2] = {70, 64}, END[2] = {230, 176};
static const int32_t TOP[3] = {200, 45, 40}, BOTTOM[3] = {45, 65, 185};

/* The frame buffer and the tracker's memory, in .bss. */
static uint8_t frame_buffer[FRAME_BYTES];
#ifdef CF_FIRMWARE
static _Alignas(RBT_TRACKER_ALIGN) uint8_t tracker_memory[RBT_TRACKER_CF_SIZE];
#else
static _Alignas(RBT_TRACKER_ALIGN) uint8_t tracker_memory[RBT_TRACKER_RGB_100_SIZE];
#endif
_Static_assert(_Alignof(tracker_memory) >= RBT_TRACKER_ALIGN, "tracker memory misaligned");

/* The scene's 32-bit hash of three coordinates and a seed. */
static uint32_t hash(uint32_t a, uint32_t b, uint32_t c, uint32_t seed) {
    uint32_t h = a * 0x9E3779B1u ^ b * 0x85EBCA77u ^ c * 0xC2B2AE3Du ^ seed * 0x27D4EB2Fu;
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    h *= 0x846CA68Bu;
    return h ^ (h >> 16);
}

/* A value in -amp..=amp from 8 bits of h. */
static int32_t spread(uint32_t h, int32_t amp) {
    return (((int32_t)(h & 0xFF) * (2 * amp + 1)) >> 8) - amp;
}

/* The floor colour at grid node (gx, gy). */
static void node_colour(uint32_t gx, uint32_t gy, int32_t rgb[3]) {
    uint32_t h = hash(gx, gy, 0xF1004000u, SEED);
    int32_t base = 90 + (int32_t)(h & 0x3F);
    rgb[0] = base + spread(h >> 6, 12);
    rgb[1] = base + 8 + spread(h >> 14, 12);
    rgb[2] = base - 12 + spread(h >> 22, 10);
}

/* Q16.16 product, rounded half up, saturating (the core's Q16 multiplication). */
static int32_t q16_mul(int32_t a, int32_t b) {
    int64_t v = ((int64_t)a * b + (1 << 15)) >> 16;
    return v > INT32_MAX ? INT32_MAX : v < INT32_MIN ? INT32_MIN : (int32_t)v;
}

/* The target's ellipse at `frame`: centre (cx, cy), half-axes (hx, hy), Q16.16. */
typedef struct { int32_t cx, cy, hx, hy; } ellipse;

static ellipse truth(int32_t frame) {
    int64_t t = frame;
    ellipse e;
    e.cx = (int32_t)(((int64_t)START[0] << 16) + (((int64_t)(END[0] - START[0]) * t) << 16) / FRAMES);
    e.cy = (int32_t)(((int64_t)START[1] << 16) + (((int64_t)(END[1] - START[1]) * t) << 16) / FRAMES);
    e.hy = q16_mul(q16_mul(e.cy - (HORIZON_Y << 16), SCALE_PER_ROW), RBT_Q16_ONE);
    e.hx = (int32_t)(((int64_t)e.hy * 7) >> 4);
    return e;
}

/* 128-bit unsigned value, for the ellipse test's squares of 50-bit products. */
typedef struct { uint64_t hi, lo; } u128;

static u128 square(uint64_t v) {
    uint64_t a = v >> 32, b = v & 0xFFFFFFFFu;
    uint64_t cross = a * b, low = b * b;
    u128 r = {a * a + (cross >> 31), low + (cross << 33)};
    if (r.lo < low) r.hi++;
    return r;
}

static u128 add(u128 x, u128 y) {
    u128 r = {x.hi + y.hi, x.lo + y.lo};
    if (r.lo < x.lo) r.hi++;
    return r;
}

static int at_most(u128 x, u128 y) { return x.hi < y.hi || (x.hi == y.hi && x.lo <= y.lo); }

static uint64_t magnitude(int64_t v) { return v < 0 ? (uint64_t)-v : (uint64_t)v; }

/* Renders `frame` of the scene into frame_buffer: RGB565 little-endian, stride WIDTH. */
static void render(int32_t frame) {
    ellipse e = truth(frame);
    int64_t cx = e.cx, cy = e.cy, hx = e.hx, hy = e.hy;
    u128 limit = square((uint64_t)(hx * hy));
    const int32_t g = 1 << GRID_LOG2;
    uint8_t *px = frame_buffer;
    for (int32_t y = 0; y < HEIGHT; y++) {
        int32_t fy = y & (g - 1);
        int64_t dy = ((int64_t)y << 16) - cy;
        u128 dy_hx = square(magnitude(dy * hx));
        for (int32_t x = 0; x < WIDTH; x++, px += 2) {
            int64_t dx = ((int64_t)x << 16) - cx;
            int32_t rgb[3];
            if (at_most(add(square(magnitude(dx * hy)), dy_hx), limit)) {
                const int32_t *base = dy < 0 ? TOP : BOTTOM;
                int32_t t = (int32_t)((dx * 256) / (hx > 1 ? hx : 1));
                int32_t shade = 256 - ((t * t) >> 8) * 2 / 5;
                for (int k = 0; k < 3; k++) rgb[k] = (base[k] * shade) >> 8;
            } else {
                int32_t c00[3], c10[3], c01[3], c11[3];
                uint32_t gx = (uint32_t)x >> GRID_LOG2, gy = (uint32_t)y >> GRID_LOG2;
                int32_t fx = x & (g - 1);
                node_colour(gx, gy, c00);
                node_colour(gx + 1, gy, c10);
                node_colour(gx, gy + 1, c01);
                node_colour(gx + 1, gy + 1, c11);
                int32_t texture = spread(hash((uint32_t)x, (uint32_t)y, 0x7E270000u, SEED), TEXTURE);
                for (int k = 0; k < 3; k++) {
                    int32_t top = c00[k] * (g - fx) + c10[k] * fx;
                    int32_t bottom = c01[k] * (g - fx) + c11[k] * fx;
                    rgb[k] = ((top * (g - fy) + bottom * fy) >> (2 * GRID_LOG2)) + texture;
                }
            }
            uint32_t noise = hash((uint32_t)x, (uint32_t)y, (uint32_t)frame, SEED);
            for (int k = 0; k < 3; k++) {
                int32_t c = rgb[k] + spread(noise >> (8 * k), NOISE);
                rgb[k] = c < 0 ? 0 : c > 255 ? 255 : c;
            }
            uint16_t v = (uint16_t)(((rgb[0] >> 3) << 11) | ((rgb[1] >> 2) << 5) | (rgb[2] >> 3));
            px[0] = (uint8_t)v;
            px[1] = (uint8_t)(v >> 8);
        }
    }
}

/* 64-bit FNV-1a over little-endian 32-bit words. */
static uint64_t fnv_word(uint64_t h, uint32_t word) {
    for (int i = 0; i < 4; i++) {
        h ^= (word >> (8 * i)) & 0xFF;
        h *= 0x00000100000001B3ull;
    }
    return h;
}

static uint64_t add_estimate(uint64_t h, const rbt_estimate *e) {
    const int32_t fields[7] = {e->cx, e->cy, e->hx, e->hy, e->vx, e->vy, e->confidence};
    for (int i = 0; i < 7; i++) h = fnv_word(h, (uint32_t)fields[i]);
    /* The checksum's status numbers: 0 tracking, 1 uncertain, 2 lost. */
    uint32_t status = e->status == RBT_STATUS_TRACKING ? 0 : e->status == RBT_STATUS_UNCERTAIN ? 1 : 2;
    return fnv_word(h, status);
}

/* Prints `text`, then `value` in hexadecimal with 16 digits. */
static void print_hex(const char *text, uint64_t value) {
    char line[32] = "0x";
    for (int i = 0; i < 16; i++) line[2 + i] = "0123456789abcdef"[(value >> (60 - 4 * i)) & 0xF];
    line[18] = '\n';
    line[19] = 0;
    semihosting_write(text);
    semihosting_write(line);
}

static int fail(const char *what, rbt_error e) {
    semihosting_write(what);
    semihosting_write(": ");
    semihosting_write(rbt_error_name(e));
    semihosting_write("\n");
    return 1;
}

/* Prints the stack's high-water mark. */
static void print_stack_used(void) {
    char digits[12] = {0};
    char *at = digits + sizeof digits - 1;
    uint32_t stack = stack_used();
    do *--at = (char)('0' + stack % 10); while ((stack /= 10) > 0);
    semihosting_write("stack high-water mark: ");
    semihosting_write(at);
    semihosting_write(" bytes\n");
}

/* The first frame's box: the true ellipse's bounding box, which the tracker turns back
 * into it exactly. */
static rbt_rect first_box(void) {
    ellipse e = truth(0);
    rbt_rect box = {e.cx - e.hx + RBT_Q16_ONE / 2, e.cy - e.hy + RBT_Q16_ONE / 2, 2 * e.hx, 2 * e.hy};
    return box;
}

/* The FNV-1a offset basis: an empty checksum. */
#define FNV_OFFSET 0xCBF29CE484222325ull

/* Renders and tracks frames 1..=FRAMES, folding every estimate into each of the `n`
 * checksums at `sums`. */
static rbt_error track_frames(rbt_tracker *tracker, const rbt_image *image, uint64_t *sums, int n) {
    for (int32_t frame = 1; frame <= FRAMES; frame++) {
        render(frame);
        rbt_estimate estimate;
        rbt_error err = rbt_step(tracker, image, &estimate);
        if (err != RBT_OK) return err;
        for (int i = 0; i < n; i++) sums[i] = add_estimate(sums[i], &estimate);
    }
    return RBT_OK;
}

#ifdef CF_FIRMWARE
int main(void) {
    semihosting_write("rbtrack C correlation-filter firmware: 320x240 RGB565 scene, seed 1, 60 frames; 16 x 16 cells, 4 scales\n");
    rbt_tracker *tracker;
    rbt_error err = rbt_tracker_place_cf(tracker_memory, sizeof tracker_memory, &tracker);
    if (err != RBT_OK) return fail("place", err);
    const rbt_image image = {.data = frame_buffer, .size = sizeof frame_buffer, .width = WIDTH,
                             .height = HEIGHT, .stride = WIDTH, .format = RBT_FORMAT_RGB565LE};
    rbt_cf_config config;
    err = rbt_cf_config_default(&config);
    if (err != RBT_OK) return fail("config", err);
    rbt_rect box = first_box();
    render(0);
    err = rbt_cf_start(tracker, &config, &image, &box);
    if (err != RBT_OK) return fail("start", err);
    uint64_t checksum = FNV_OFFSET;
    err = track_frames(tracker, &image, &checksum, 1);
    if (err != RBT_OK) return fail("step", err);
    print_stack_used();
    print_hex("cf checksum ", checksum);
    return 0;
}
#else
int main(void) {
    semihosting_write("rbtrack C example firmware: 320x240 RGB565 scene, seed 1, 60 frames; N = 100, 512 bins\n");
    rbt_tracker *tracker;
    rbt_error err = rbt_tracker_place_rgb_100(tracker_memory, sizeof tracker_memory, &tracker);
    if (err != RBT_OK) return fail("place", err);
    const rbt_image image = {.data = frame_buffer, .size = sizeof frame_buffer, .width = WIDTH,
                             .height = HEIGHT, .stride = WIDTH, .format = RBT_FORMAT_RGB565LE};
    const uint32_t variants[2] = {RBT_VARIANT_RBPF, RBT_VARIANT_COLOUR_PF};
    uint64_t checksum = FNV_OFFSET;
    for (int v = 0; v < 2; v++) {
        rbt_config config;
        err = rbt_config_default(variants[v], &config);
        if (err != RBT_OK) return fail("config", err);
        config.seed = TRACKER_SEED;
        if (variants[v] == RBT_VARIANT_RBPF) config.scale_per_row = SCALE_PER_ROW;
        rbt_rect box = first_box();
        render(0);
        err = rbt_start(tracker, &config, &image, &box);
        if (err != RBT_OK) return fail("start", err);
        /* The run's own checksum, and the one over both runs. */
        uint64_t sums[2] = {FNV_OFFSET, checksum};
        err = track_frames(tracker, &image, sums, 2);
        if (err != RBT_OK) return fail("step", err);
        checksum = sums[1];
        print_hex(variants[v] == RBT_VARIANT_RBPF ? "rbpf: checksum " : "pf: checksum ", sums[0]);
    }
    print_stack_used();
    print_hex("checksum ", checksum);
    return 0;
}
#endif
