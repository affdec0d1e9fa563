/* hal-pic: the program's declared parameters (hal_param_table; the build
 * defines HAL_PARAM_NO_TEXT, so the table holds names, ranges and defaults
 * only), with values compiled in. No value is compiled in by default (every
 * hal_param returns its default); a build can give some by defining
 * HAL_PIC_PARAMS as a list of entries, e.g.
 *     -DHAL_PIC_PARAMS='{"control_ms", 10}, {"poll_ms", 500},'
 * Each value is clamped to its declared range, as in the simulator. */
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

/* the compiled-in entry of name, or 0 */
static const hp_param *given(const char *name)
{
#ifdef HAL_PIC_PARAMS
    uint8_t i;
    for (i = 0; i < N_PARAMS; i++)
        if (same(params[i].name, name))
            return &params[i];
#else
    (void)name;
#endif
    return 0;
}

int32_t hal_param(const char *name)
{
    const hal_param_decl *d = declared(name);
    const hp_param *p;
    int32_t v;
    if (d == 0)
        return 0;
    p = given(name);
    if (p == 0)
        return d->def;
    v = p->value;
    if (v < d->min)
        return d->min;
    if (v > d->max)
        return d->max;
    return v;
}

uint8_t hal_param_given(const char *name)
{
    return declared(name) != 0 && given(name) != 0;
}
