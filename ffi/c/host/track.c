/* Tracks a raw RGB888 sequence through the C API and prints one box a line.
 *
 *     track FRAMES WIDTH HEIGHT X,Y,W,H [rbpf|pf|cf] [SEED]
 *
 * FRAMES holds WIDTH x HEIGHT RGB888 frames back to back (`rbtrack frames SEQ FRAMES`
 * writes one); X,Y,W,H is the target's 0-based box in the first frame, px. Prints the
 * box of every frame as `x,y,w,h` with two decimals, the first frame's being the given
 * box: the lines `rbtrack track FRAMES --raw WIDTHxHEIGHT:rgb888 --init X,Y,W,H
 * --zero-based --boxes FILE --tracker T` writes for the same tracker and seed (default
 * rbpf, 1; cf, the correlation-filter tracker at its defaults, takes no seed).
 * Exits 1 with a message on any error. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rbtrack.h"

/* The tracker, in memory this program owns: room for either kind, the particle filter of
 * 100 particles on 512 RGB bins or the correlation-filter tracker. */
#define TRACKER_SIZE \
    (RBT_TRACKER_CF_SIZE > RBT_TRACKER_RGB_100_SIZE ? RBT_TRACKER_CF_SIZE : RBT_TRACKER_RGB_100_SIZE)
static _Alignas(RBT_TRACKER_ALIGN) unsigned char tracker_memory[TRACKER_SIZE];
_Static_assert(_Alignof(tracker_memory) >= RBT_TRACKER_ALIGN, "tracker memory misaligned");

static int fail(const char *what, rbt_error e) {
    fprintf(stderr, "track: %s: %s\n", what, rbt_error_name(e));
    return 1;
}

/* A Q16.16 value as a decimal with two places. */
static double px(rbt_q16 v) { return v / (double)RBT_Q16_ONE; }

static void print_box(rbt_rect r) {
    printf("%.2f,%.2f,%.2f,%.2f\n", px(r.x), px(r.y), px(r.w), px(r.h));
}

int main(int argc, char **argv) {
    int x, y, w, h;
    if (argc < 5 || sscanf(argv[4], "%d,%d,%d,%d", &x, &y, &w, &h) != 4) {
        fprintf(stderr, "usage: track FRAMES WIDTH HEIGHT X,Y,W,H [rbpf|pf|cf] [SEED]\n");
        return 2;
    }
    uint32_t width = (uint32_t)strtoul(argv[2], NULL, 10);
    uint32_t height = (uint32_t)strtoul(argv[3], NULL, 10);
    int correlation = argc > 5 && strcmp(argv[5], "cf") == 0;
    uint32_t variant = argc > 5 && strcmp(argv[5], "pf") == 0 ? RBT_VARIANT_COLOUR_PF : RBT_VARIANT_RBPF;
    FILE *in = fopen(argv[1], "rb");
    if (!in) {
        perror(argv[1]);
        return 1;
    }
    size_t frame_bytes = (size_t)width * height * 3;
    unsigned char *pixels = malloc(frame_bytes ? frame_bytes : 1);
    if (!pixels) {
        fprintf(stderr, "track: out of memory\n");
        return 1;
    }

    rbt_config config;
    rbt_cf_config cf_config;
    rbt_error e = correlation ? rbt_cf_config_default(&cf_config) : rbt_config_default(variant, &config);
    if (e != RBT_OK) return fail("config", e);
    if (argc > 6 && !correlation) config.seed = strtoull(argv[6], NULL, 10);
    char why[96];
    e = correlation ? rbt_cf_config_check(&cf_config, why, sizeof why) : rbt_config_check(&config, why, sizeof why);
    if (e != RBT_OK) return fail(why, e);

    rbt_tracker *tracker;
    e = correlation ? rbt_tracker_place_cf(tracker_memory, sizeof tracker_memory, &tracker)
                    : rbt_tracker_place_rgb_100(tracker_memory, sizeof tracker_memory, &tracker);
    if (e != RBT_OK) return fail("place", e);

    rbt_image frame = {.data = pixels, .size = frame_bytes, .width = width, .height = height,
                       .stride = width, .format = RBT_FORMAT_RGB888};
    rbt_rect box = {x * RBT_Q16_ONE, y * RBT_Q16_ONE, w * RBT_Q16_ONE, h * RBT_Q16_ONE};
    for (size_t n = 0; fread(pixels, 1, frame_bytes, in) == frame_bytes; n++) {
        if (n == 0) {
            e = correlation ? rbt_cf_start(tracker, &cf_config, &frame, &box)
                            : rbt_start(tracker, &config, &frame, &box);
            if (e != RBT_OK) return fail("start", e);
            print_box(box);
            continue;
        }
        rbt_estimate estimate;
        e = rbt_step(tracker, &frame, &estimate);
        if (e != RBT_OK) return fail("step", e);
        print_box(estimate.rect);
    }
    fclose(in);
    free(pixels);
    return 0;
}
