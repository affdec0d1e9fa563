/* Elbow negotiation: see elbow.h. */
#include "elbow.h"

#include "central_io.h"
#include "central_params.h"
#include "fixed_sin.h"
#include "gaits.h"

static int16_t bend_pitch, bend_yaw; /* cdeg, held while bending */
static uint8_t bending, bent_once;
uint32_t elbow_bend_end; /* when the bend ends (while bending) or ended */

void elbow_setup(void)
{
    if (params.elbow_dir_deg >= 0) {
        /* direction in mrad = deg * 17.453; a positive pitch bends the
         * chain up, a negative yaw to the left (as the turn gait's offset;
         * measured in the simulator, docs/firmware.md) */
        int32_t d = (int32_t)params.elbow_dir_deg * 17453L / 1000L;
        bend_pitch = fs_scale(params.bend_cdeg, fs_cos_mrad(d));
        bend_yaw = (int16_t)-fs_scale(params.bend_cdeg, fs_sin_mrad(d));
    }
}

void elbow_log(void)
{
    if (params.elbow_dir_deg < 0)
        return;
    sb_reset(&cio_sb);
    cio_put("elbow: dir_deg=", params.elbow_dir_deg);
    cio_put(" pitch_cdeg=", bend_pitch);
    cio_put(" yaw_cdeg=", bend_yaw);
    cio_put(" bend_ms=", params.bend_ms);
    cio_log_line(cio_sb.buf);
}

void elbow_contact(uint32_t now)
{
    if (params.elbow_dir_deg < 0 || bending)
        return;
    if (bent_once && (int32_t)(now - elbow_bend_end) < (int32_t)params.bend_ms)
        return; /* the same elbow: the head meets the outgoing leg's wall */
    gaits_send_bend(bend_pitch, bend_yaw);
    cio_log_int("elbow: bend at ms ", now);
    bending = 1;
    bent_once = 1;
    elbow_bend_end = now + params.bend_ms;
}

uint8_t elbow_update(uint32_t now, uint8_t stopped)
{
    if (!bending)
        return 0;
    if (stopped) {
        bending = 0; /* STOP has straightened them */
        return 0;
    }
    if ((int32_t)(now - elbow_bend_end) >= 0) {
        gaits_send_bend(0, 0);
        bending = 0;
        cio_log_int("elbow: straight at ms ", now);
        return 0;
    }
    return 1;
}
