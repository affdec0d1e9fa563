/* Named integer parameters given to the program by the scene (simulator) or
 * compiled in (board). */
#ifndef HAL_PARAM_H
#define HAL_PARAM_H

#include <stdint.h>

#define HAL_PARAM_NAME_MAX 15u /* characters of a parameter name (the simulator's limit) */

/* value of parameter name, or default_value when it is not set */
int32_t hal_param(const char *name, int32_t default_value);

#endif
