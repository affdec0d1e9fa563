/* A module program whose parameter table is wrong on purpose (a default
 * outside its range), for program_params_test: hal-sim refuses to list it. */
#include "hal.h"

const hal_param_decl hal_param_table[] = {
    HAL_PARAM("fine", HAL_PARAM_U8, 0, 9, 3, "a good declaration"),
    HAL_PARAM("level", HAL_PARAM_I16, 0, 100, 200, "a default above its max"),
    HAL_PARAM_END
};

int main(void)
{
    hal_init();
    for (;;)
        hal_delay_ms((uint16_t)hal_param("fine"));
}
