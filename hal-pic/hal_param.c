/* hal-pic: parameters compiled in. The table is empty by default (every
 * hal_param returns its default_value); a build can fill it by defining
 * HAL_PIC_PARAMS as a list of entries, e.g.
 *     -DHAL_PIC_PARAMS='{"control_ms", 10}, {"poll_ms", 500},'
 */
#include "hal_param.h"

#include "hal_pic.h"

typedef struct {
    const char *name;
    int32_t value;
} hp_param;

#ifdef HAL_PIC_PARAMS
static const hp_param params[] = { HAL_PIC_PARAMS };
#define N_PARAMS (sizeof params / sizeof params[0])
#endif

#ifdef HAL_PIC_PARAMS
static uint8_t same(const char *a, const char *b)
{
    while (*a != '\0' && *a == *b) {
        a++;
        b++;
    }
    return *a == *b;
}
#endif

int32_t hal_param(const char *name, int32_t default_value)
{
#ifdef HAL_PIC_PARAMS
    uint8_t i;
    if (name == 0)
        return default_value;
    for (i = 0; i < N_PARAMS; i++)
        if (same(params[i].name, name))
            return params[i].value;
#else
    (void)name;
#endif
    return default_value;
}
