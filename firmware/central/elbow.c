/* Elbow negotiation: see elbow.h. */
#include "elbow.h"

#include "central_io.h"
#include "central_params.h"
#include "fixed_sin.h"
#include "discovery.h"
#include "gaits.h"
#include "chain_commands.h"

#define ELBOW_OFF (-2) /* elbow_dir_deg: no steering */

static int16_t bend_pitch, bend_yaw; /* cdeg, held while bending */
static uint8_t bending, bent_once;
static uint8_t holding;    /* the support modules grip (hold_ms) */
static uint32_t t_release; /* when they let go */
static uint8_t steers; /* gait 9, steering not off, and a rotation module to bend (set once the chain is known) */
uint32_t elbow_bend_end; /* when the steering ended */
uint32_t elbow_wake;     /* the next change: a bend, a straightening, a contact's window ending */

/* the bend toward dir_deg */
static void set_direction(int16_t dir_deg)
{
    /* direction in mrad = deg * 17.453; a positive pitch bends the chain
     * up, a negative yaw to the left (as the turn gait's offset; measured in
     * the simulator, docs/firmware.md) */
    int32_t d = (int32_t)dir_deg * 17453L / 1000L;
    bend_pitch = fs_scale(params.bend_cdeg, fs_cos_mrad(d));
    bend_yaw = (int16_t)-fs_scale(params.bend_cdeg, fs_sin_mrad(d));
}

static uint8_t rotation_from(uint8_t i, uint8_t from, uint32_t *t);

/* the side the junction policy takes, CC_SIDE_LEFT or CC_SIDE_RIGHT (its
 * angle as gravity gives it is 90 degrees per CC_SIDE_ step) */
static uint8_t junction_side(void)
{
    return params.junction == JUNCTION_LEFT ? CC_SIDE_LEFT : CC_SIDE_RIGHT;
}

void elbow_setup(void)
{
    uint32_t t = 0;
    steers = params.gait == GAIT_HELICOIDAL && params.elbow_dir_deg != ELBOW_OFF &&
             rotation_from(0, chain_n_modules, &t) < chain_n_modules;
    if (params.elbow_dir_deg >= 0)
        set_direction(params.elbow_dir_deg);
}

void elbow_log(void)
{
    if (!steers)
        return;
    sb_reset(&cio_sb);
    if (params.elbow_dir_deg >= 0) {
        cio_put("elbow: dir_deg=", params.elbow_dir_deg);
        cio_put(" pitch_cdeg=", bend_pitch);
        cio_put(" yaw_cdeg=", bend_yaw);
    } else {
        sb_str(&cio_sb, "elbow: sensed");
        cio_put(" bend_cdeg=", params.bend_cdeg);
    }
    cio_put(" bend_ms=", params.bend_ms);
    if (params.bend_travel_ms != 0)
        cio_put(" bend_travel_ms=", params.bend_travel_ms);
    if (params.junction != JUNCTION_WAIT) {
        sb_str(&cio_sb, " junction=");
        cio_put_side(junction_side());
    }
    cio_log_line(cio_sb.buf);
}

/* The steering under way: the rotation module at chain index next_on bends
 * at t_on, the one at next_off straightens at t_off. Each bends
 * bend_travel_ms per place behind the first rotation module later than it,
 * and straightens bend_ms after it bent. The steering ends at t_end: when
 * the last one straightened (bend_ms after the contact in a chain without
 * rotation modules). Counters rather than a table per module: the PIC's RAM. */
static uint32_t t_on, t_off, t_end;
static uint8_t next_on, next_off;

/* the first rotation module at chain index i or after it (chain_n_modules:
 * none); *t moves on by bend_travel_ms for each place from `from` to it */
static uint8_t rotation_from(uint8_t i, uint8_t from, uint32_t *t)
{
    while (i < chain_n_modules && chain_module_type[i] != MT_ROTATION)
        i++;
    for (; from < i; from++)
        *t += params.bend_travel_ms;
    return i;
}

/* send the bends that are due */
static void bend_due(uint32_t now)
{
    while (next_on < chain_n_modules && (int32_t)(now - t_on) >= 0) {
        gaits_send_bend(next_on, bend_pitch, bend_yaw);
        next_on = rotation_from((uint8_t)(next_on + 1), next_on, &t_on);
    }
}

/* send the straightenings (or, bend_limp, the releases) that are due (of
 * modules already bent) */
static void straighten_due(uint32_t now)
{
    while (next_off < next_on && (int32_t)(now - t_off) >= 0) {
        if (params.bend_limp)
            gaits_send_limp(next_off);
        else
            gaits_send_bend(next_off, 0, 0);
        t_end = t_off;
        next_off = rotation_from((uint8_t)(next_off + 1), next_off, &t_off);
    }
}

/* a contact watched for JUNCTION_WINDOW_MS (junction policy): since when,
 * its first direction and up, and whether all three switches closed at once */
static uint8_t watching, watch_head_on;
static uint32_t watch_from;
static int16_t watch_dir, watch_up;

static void steer(uint32_t now, int16_t obstacle_deg, int16_t up_deg);

void elbow_contact(uint32_t now, int16_t obstacle_deg, int16_t up_deg)
{
    if (!steers || bending || holding || watching)
        return;
    if (bent_once && (int32_t)(now - elbow_bend_end) < (int32_t)params.bend_ms)
        return; /* the same elbow: the head meets the outgoing leg's wall */
    if (params.junction != JUNCTION_WAIT && params.elbow_dir_deg < 0) {
        watching = 1;
        watch_head_on = 0;
        watch_from = now;
        watch_dir = obstacle_deg;
        watch_up = up_deg;
        return;
    }
    steer(now, obstacle_deg, up_deg);
}

/* bend toward the turn that obstacle_deg (up_deg) asks for */
static void steer(uint32_t now, int16_t obstacle_deg, int16_t up_deg)
{
    int16_t turn;
    const char *why = "sensed";
    uint8_t side = CC_SIDE_NONE; /* a junction's: named in the log */
    if (params.elbow_dir_deg >= 0) {
        turn = params.elbow_dir_deg;
        why = "given";
    } else {
        if (obstacle_deg != CC_TOUCH_NONE) {
            /* the head meets the bend's outer wall: the pipe turns away from it */
            turn = (int16_t)(obstacle_deg >= 180 ? obstacle_deg - 180 : obstacle_deg + 180);
        } else if (params.junction != JUNCTION_WAIT && up_deg != CC_TOUCH_NONE) {
            /* a wall ahead: the junction policy's way, left or right of up */
            side = junction_side();
            turn = (int16_t)(up_deg + 90 * side);
            if (turn >= 360)
                turn -= 360;
            why = "junction";
        } else {
            cio_log_int("elbow: head-on contact, no direction at ms ", now);
            return;
        }
        set_direction(turn);
    }
    t_on = now; /* the first rotation module bends at the contact: */
    next_on = rotation_from(0, chain_n_modules, &t_on); /* no places counted */
    next_off = next_on;
    t_off = now + params.bend_ms;
    t_end = t_off;
    bend_due(now); /* straightenings wait for elbow_update, after this log line */
    sb_reset(&cio_sb);
    cio_put("elbow: bend at ms ", (int32_t)now);
    cio_put(" toward dir_deg=", turn);
    if (up_deg != CC_TOUCH_NONE) /* the turn as gravity gives it: 0 up, 90 left, 180 down, 270 right */
        cio_put(" world_deg=", (turn - up_deg + 360) % 360);
    sb_str(&cio_sb, " (");
    sb_str(&cio_sb, why);
    if (side != CC_SIDE_NONE) {
        sb_str(&cio_sb, ", ");
        cio_put_side(side);
    }
    sb_char(&cio_sb, ')');
    cio_log_line(cio_sb.buf);
    bending = 1;
    bent_once = 1;
    if (params.hold_ms != 0) {
        /* the support modules hold the chain while the rotation modules turn (paper 6.6) */
        gaits_send_hold(1);
        holding = 1;
        t_release = now + params.hold_ms;
        cio_log_int("elbow: hold at ms ", now);
    }
}

uint8_t elbow_update(uint32_t now, uint8_t stopped, uint8_t head_on)
{
    if (watching) {
        watch_head_on |= head_on;
        if (stopped) {
            watching = 0;
            return 0;
        }
        if ((int32_t)(now - watch_from) < (int32_t)JUNCTION_WINDOW_MS) {
            elbow_wake = watch_from + JUNCTION_WINDOW_MS;
            return 1;
        }
        watching = 0;
        /* all three switches closed within the window: a wall ahead */
        steer(now, watch_head_on ? CC_TOUCH_NONE : watch_dir, watch_up);
    }
    if (stopped) {
        bending = 0; /* STOP has straightened them */
        holding = 0; /* and the support modules keep their grip */
        return 0;
    }
    if (holding && (int32_t)(now - t_release) >= 0) {
        gaits_send_hold(0);
        holding = 0;
        cio_log_int("elbow: release at ms ", now);
    }
    if (bending) {
        bend_due(now);
        straighten_due(now);
        if (next_off >= chain_n_modules && (int32_t)(now - t_end) >= 0) {
            bending = 0;
            elbow_bend_end = t_end;
            cio_log_int(params.bend_limp ? "elbow: limp at ms " : "elbow: straight at ms ", now);
        }
    }
    /* the next change */
    if (bending) {
        elbow_wake = next_off < chain_n_modules ? t_off : t_end;
        if (next_on < chain_n_modules && (int32_t)(t_on - elbow_wake) < 0)
            elbow_wake = t_on;
        if (holding && (int32_t)(t_release - elbow_wake) < 0)
            elbow_wake = t_release;
    } else if (holding) {
        elbow_wake = t_release;
    }
    return bending | holding;
}
