/* Mistakes that are right on a PC and wrong on the PIC18, one per value of
 * the parameter `case`; each logs what it computed once (the simulator's
 * native build and the board's binary then disagree in the log), then idles.
 *   1  int x = 300 * 200           int is 16 bits on the PIC: -5536
 *   2  long big = 1 << 20          the shift is done in 16-bit int: 0
 *   3  int scaled = amp * 20       amp = 3000 from a parameter: -5536
 *   4  int32_t sq = amp * amp      multiplied in 16 bits, then widened: 21568
 *   5  recursion 40 deep           the hardware return stack holds 31: reset */
#include "hal.h"

const hal_param_decl hal_param_table[] = {
    HAL_PARAM("case", HAL_PARAM_U8, 1, 5, 1, "which mistake to make"),
    HAL_PARAM("amp", HAL_PARAM_I16, -32768, 32767, 3000, "an amplitude given at run time"),
    HAL_PARAM_END
};

static int depth(int n)
{
    if (n == 0)
        return 0;
    return depth(n - 1) + 1;
}

int main(void)
{
    int amp;
    hal_init();
    amp = (int)hal_param("amp");
    switch (hal_param("case")) {
    case 1: {
        int x = 300 * 200;
        hal_log_int("case 1: 300 * 200 = ", x);
        break;
    }
    case 2: {
        long big = 1 << 20;
        hal_log_int("case 2: 1 << 20 = ", big);
        break;
    }
    case 3: {
        int scaled = amp * 20;
        hal_log_int("case 3: amp * 20 = ", scaled);
        break;
    }
    case 4: {
        int32_t sq = amp * amp;
        hal_log_int("case 4: amp * amp = ", sq);
        break;
    }
    case 5:
        hal_log_int("case 5: depth(40) = ", depth(40));
        break;
    default:
        break;
    }
    for (;;)
        hal_delay_ms(1000);
}
