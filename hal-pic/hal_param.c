/* hal-pic: the program's declared parameters (hal_param_table; the build
 * defines HAL_PARAM_NO_TEXT, so the table holds names, ranges and defaults
 * only). A parameter's value comes from, first to last:
 *   - the data EEPROM, where a programmer writes each unit's values (layout:
 *     hal_pic_board.h, "parameters in the data EEPROM"; the simulator's PIC
 *     module process writes the scene's values there);
 *   - the build: HAL_PIC_PARAMS as a list of entries, e.g.
 *         -DHAL_PIC_PARAMS='{"control_ms", 10}, {"poll_ms", 500},'
 *   - its declared default.
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

/* the declaration of name and its index in the table, or 0 */
static const hal_param_decl *declared(const char *name, uint8_t *index)
{
    const hal_param_decl *d;
    uint8_t i = 0;
    if (name == 0)
        return 0;
    for (d = hal_param_table; d->name != 0; d++, i++) {
        if (same(d->name, name)) {
            *index = i;
            return d;
        }
    }
    return 0;
}

static uint8_t ee_read(uint8_t addr)
{
    EEADR = addr;
    EECON1bits.EEPGD = 0; /* data EEPROM, not flash */
    EECON1bits.CFGS = 0;
    EECON1bits.RD = 1;
    return EEDATA;
}

/* 1 and *v when the EEPROM holds a value for the parameter at index */
static uint8_t ee_value(uint8_t index, int32_t *v)
{
    uint8_t n, e, a, k;
    uint8_t *bytes = (uint8_t *)v; /* the PIC18 and the EEPROM layout are little-endian */
    if (ee_read(0) != HP_BOARD_PARAMS_MAGIC)
        return 0;
    n = ee_read(1);
    if (n > HP_BOARD_PARAMS_MAX)
        return 0;
    for (e = 0, a = 2; e < n; e++, a = (uint8_t)(a + HP_BOARD_PARAMS_ENTRY_BYTES)) {
        if (ee_read(a) == index) {
            for (k = 0; k < 4u; k++)
                bytes[k] = ee_read((uint8_t)(a + 1u + k));
            return 1;
        }
    }
    return 0;
}

/* 1 and *v when the EEPROM or the build gives the parameter a value */
static uint8_t given(const char *name, uint8_t index, int32_t *v)
{
#ifdef HAL_PIC_PARAMS
    uint8_t i;
#endif
    if (ee_value(index, v))
        return 1;
#ifdef HAL_PIC_PARAMS
    for (i = 0; i < N_PARAMS; i++) {
        if (same(params[i].name, name)) {
            *v = params[i].value;
            return 1;
        }
    }
#else
    (void)name;
#endif
    return 0;
}

int32_t hal_param(const char *name)
{
    uint8_t index = 0;
    int32_t v;
    const hal_param_decl *d = declared(name, &index);
    if (d == 0)
        return 0;
    if (!given(name, index, &v))
        return d->def;
    return v < d->min ? d->min : v > d->max ? d->max : v;
}

uint8_t hal_param_given(const char *name)
{
    uint8_t index = 0;
    int32_t v;
    return declared(name, &index) != 0 && given(name, index, &v);
}
