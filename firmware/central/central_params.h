/* The central control's parameters (the scene's central.params, hal_param),
 * read once after discovery. Every parameter's name, range, default and
 * meaning is in central_params.c's hal_param_table and nowhere else;
 * `chainsim params fw-central` and docs/firmware.md list them. */
#ifndef CENTRAL_PARAMS_H
#define CENTRAL_PARAMS_H

#include <stdint.h>

typedef struct {
    /* the gait and its wave (gaits 1-7) */
    uint8_t gait;          /* gait code, 0 = don't start */
    int16_t amp_cdeg;      /* amplitude A */
    int16_t omega_mrad_s;  /* angular velocity */
    int16_t phase_mrad;    /* phase step between modules */
    uint8_t axis;          /* CC_AXIS_* */
    int16_t posture_cdeg;  /* zig-zag of the other axis */
    int16_t amp2_cdeg;     /* yaw wave of roll, rotate, lateral shift */
    int16_t shift_mrad;    /* yaw wave's phase against the pitch wave */
    int16_t bias_cdeg;     /* yaw offset of the turns */
    /* gait 9 (helicoidal drive) and gait 8 (inchworm) */
    int16_t drive_permille;
    int16_t step_ms;
    int16_t grip_cdeg;
    int16_t stroke_um;
    uint8_t inchworm_all; /* gait 8 as gait 13 on the bus: every extension at once (paper 6.5) */
    /* schedule */
    uint32_t start_ms;     /* START at this simulated time */
    uint32_t stop_ms;      /* STOP at this time, 0 = never */
    uint32_t poll_ms;      /* READ_SENSORS every poll_ms, 0 = never */
    /* elbows (gait 9): which way the pipe turns relative to the chain (0 up,
     * 90 left, 180 down, 270 right; -1 = sensed, -2 = off), which way to take
     * where the head meets a wall ahead (JUNCTION_*), how far and how long to
     * bend */
    int16_t elbow_dir_deg;
    uint8_t junction;
    int16_t bend_cdeg;
    uint16_t bend_ms;
    uint16_t bend_travel_ms; /* delay of the bend per module along the chain */
    uint8_t bend_limp;       /* after bend_ms the rotation modules go limp instead of straightening */
    uint16_t hold_ms;        /* the support modules grip this long from the bend, 0 = never */
    uint16_t stall_counts;   /* a helicoidal module's current (ADC counts) that is an elbow, 0 = none */
    /* gait switching (gait 9; paper 6.7): a helicoidal module's current at
     * which the supports and extensions take over with the inchworm, and for
     * how long before the helicoidal drive is tried alone again */
    uint16_t switch_counts;  /* ADC counts, 0 = never switch */
    uint16_t switch_ms;
} central_params;

/* the parameters as read by central_params_read (a global: SDCC reaches it
 * by direct addressing, cheaper than through a pointer) */
extern central_params params;

/* junction: the way taken where the touch module is pushed head-on */
#define JUNCTION_WAIT 0u  /* none: log the contact and go on pushing */
#define JUNCTION_LEFT 1u  /* the left outlet (left as gravity gives it) */
#define JUNCTION_RIGHT 2u /* the right outlet */

/* read every parameter (hal_param clamps each to its declared range) */
void central_params_read(void);

#endif
