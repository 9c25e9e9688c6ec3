/* The C API as a C program sees it; tests/from_c.rs compiles this file against
 * include/rbtrack.h (-Wall -Wextra -Werror), links librbtrack_ffi.a and runs it.
 *
 * - rbt_status is numbered from least to most sure, and the library reads those numbers
 *   so: the pan/tilt head holds on an RBT_STATUS_LOST estimate and follows an
 *   RBT_STATUS_UNCERTAIN or RBT_STATUS_TRACKING one.
 * - rbt_error_name takes an rbt_error, and names every code as the header spells it.
 *
 * Prints each failure and exits 1 if there is one. */
#include <stdio.h>
#include <string.h>

#include "rbtrack.h"

_Static_assert(RBT_STATUS_LOST == 0 && RBT_STATUS_UNCERTAIN == 1 && RBT_STATUS_TRACKING == 2,
               "rbt_status is numbered from least to most sure");

/* Compiles only while rbt_error_name takes an rbt_error (incompatible pointer types). */
static const char *(*const error_name)(rbt_error) = rbt_error_name;

#define CODE(code) {code, #code}

/* Every code, in the header's order. */
static const struct {
    rbt_error code;
    const char *name;
} CODES[] = {
    CODE(RBT_OK),
    CODE(RBT_ERR_NULL),
    CODE(RBT_ERR_MEMORY_SIZE),
    CODE(RBT_ERR_MEMORY_ALIGN),
    CODE(RBT_ERR_NOT_A_TRACKER),
    CODE(RBT_ERR_NOT_A_PANTILT),
    CODE(RBT_ERR_FORMAT),
    CODE(RBT_ERR_IMAGE_EMPTY),
    CODE(RBT_ERR_IMAGE_TOO_LARGE),
    CODE(RBT_ERR_IMAGE_STRIDE),
    CODE(RBT_ERR_IMAGE_ODD_YUV),
    CODE(RBT_ERR_IMAGE_SHORT),
    CODE(RBT_ERR_CONFIG_ENUM),
    CODE(RBT_ERR_CONFIG_RANGE),
    CODE(RBT_ERR_CONFIG_KALMAN),
    CODE(RBT_ERR_PARTICLE_COUNT),
    CODE(RBT_ERR_BOX_TOO_SMALL),
    CODE(RBT_ERR_BOX_OUTSIDE),
    CODE(RBT_ERR_MODEL_SETTINGS),
    CODE(RBT_ERR_STATUS),
    CODE(RBT_ERR_PANTILT_FRAME),
    CODE(RBT_ERR_PANTILT_FOV),
    CODE(RBT_ERR_PANTILT_GAIN),
    CODE(RBT_ERR_PANTILT_LIMIT),
    CODE(RBT_ERR_PANTILT_RANGE),
    CODE(RBT_ERR_TRACKER_KIND),
};

static int failures = 0;

static void check(int ok, const char *what, const char *detail) {
    if (!ok) {
        printf("FAILED %s: %s\n", what, detail);
        failures++;
    }
}

/* Steps a fresh head once on a target right of the centre of a 320 x 240 px frame, seen
 * with `status`, and writes its pan command to `pan`. */
static rbt_error step_head(uint32_t status, rbt_q16 *pan) {
    rbt_pantilt_config config;
    rbt_pantilt head;
    rbt_command command = {0, 0};
    rbt_estimate seen = {.cx = 260 * RBT_Q16_ONE, .cy = 120 * RBT_Q16_ONE, .hx = 10 * RBT_Q16_ONE,
                         .hy = 10 * RBT_Q16_ONE, .status = status};
    rbt_error e = rbt_pantilt_config_default(320, 240, 60 * RBT_Q16_ONE, 45 * RBT_Q16_ONE, &config);
    if (e == RBT_OK) e = rbt_pantilt_start(&head, &config);
    if (e == RBT_OK) e = rbt_pantilt_step(&head, &seen, &command);
    *pan = command.pan;
    return e;
}

int main(void) {
    const size_t count = sizeof CODES / sizeof CODES[0];
    for (size_t i = 0; i < count; i++) {
        const char *name = error_name(CODES[i].code);
        size_t length = strlen(CODES[i].name);
        check((size_t)CODES[i].code == i, CODES[i].name, "out of order");
        check(strncmp(name, CODES[i].name, length) == 0 && name[length] == ':', CODES[i].name, name);
    }
    const char *unknown = error_name((rbt_error)count);
    check(strcmp(unknown, "unknown rbt_error code") == 0, "a value past the codes", unknown);

    rbt_q16 pan;
    check(step_head(RBT_STATUS_LOST, &pan) == RBT_OK && pan == 0, "RBT_STATUS_LOST", "the head moved");
    check(step_head(RBT_STATUS_UNCERTAIN, &pan) == RBT_OK && pan > 0, "RBT_STATUS_UNCERTAIN",
          "the head held");
    check(step_head(RBT_STATUS_TRACKING, &pan) == RBT_OK && pan > 0, "RBT_STATUS_TRACKING",
          "the head held");
    check(step_head(3, &pan) == RBT_ERR_STATUS, "status 3", "not refused with RBT_ERR_STATUS");

    printf("%zu error codes named; statuses lost 0, uncertain 1, tracking 2; %d failed\n", count,
           failures);
    return failures != 0;
}
