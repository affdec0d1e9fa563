/* hal-pic: the program's declared parameters (hal_param_table; the build
 * defines HAL_PARAM_NO_TEXT, so the table holds names, ranges and defaults
 * only), with values compiled in. No value is compiled in by default (every
 * hal_param returns its default); a build can give some by defining
 * HAL_PIC_PARAMS as a list of entries, e.g.
 *     -DHAL_PIC_PARAMS='{"control_ms", 10}, {"poll_ms", 500},'
 * Each value is clamped to its declared range, as in the simulator. */
#include "hal_param.h"

#include "hal_pic.h"

#ifdef HAL_PIC_PARAMS
typedef struct {
    const char *name;
    int32_t value;
} hp_param;

static const hp_param params[] = { HAL_PIC_PARAMS };
#define N_PARAMS (sizeof params / sizeof params[0])
#endif

static uint8_t same(const char *a, const char *b)
{
    while (*a != '\0' && *a == *b) {
        a++;
        b++;
    }
    return *a == *b;
}

/* the declaration of name, or 0 */
static const hal_param_decl *declared(const char *name)
{
    const hal_param_decl *d;
    if (name == 0)
        return 0;
    for (d = hal_param_table; d->name != 0; d++)
        if (same(d->name, name))
            return d;
    return 0;
}

#ifdef HAL_PIC_PARAMS
/* the compiled-in entry of name, or 0 */
static const hp_param *given(const char *name)
{
    uint8_t i;
    for (i = 0; i < N_PARAMS; i++)
        if (same(params[i].name, name))
            return &params[i];
    return 0;
}
#endif

int32_t hal_param(const char *name)
{
    const hal_param_decl *d = declared(name);
    if (d == 0)
        return 0;
#ifdef HAL_PIC_PARAMS
    {
        const hp_param *p = given(name);
        if (p != 0)
            return p->value < d->min ? d->min : p->value > d->max ? d->max : p->value;
    }
#endif
    return d->def; /* no value compiled in: the clamping costs no flash */
}

uint8_t hal_param_given(const char *name)
{
#ifdef HAL_PIC_PARAMS
    return declared(name) != 0 && given(name) != 0;
#else
    (void)name;
    return 0; /* nothing is compiled in */
#endif
}
