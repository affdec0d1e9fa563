/* hal-sim: the named parameters the server sent in WELCOME. */
#include "hal_param.h"

#include <string.h>

#include "hal_sim_link.h"

/* WELCOME's name buffer holds a HAL name and its NUL */
typedef char hs_param_name_check[(HAL_PARAM_NAME_MAX + 1u == CS_PARAM_NAME_MAX) ? 1 : -1];

int32_t hal_param(const char *name, int32_t default_value)
{
    uint8_t i;
    if (name == NULL)
        return default_value;
    for (i = 0; i < hs.n_params && i < CS_PARAMS_MAX; i++)
        if (strncmp(hs.params[i].name, name, CS_PARAM_NAME_MAX) == 0)
            return hs.params[i].value;
    return default_value;
}
