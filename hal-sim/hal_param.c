/* hal-sim: the program's declared parameters (hal_param_table), the values
 * the server sent in WELCOME, and the listing the server reads before a run
 * (CS_PARAMS_ARG, chainsim_protocol.h). */
#include "hal_param.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hal_sim_link.h"

/* WELCOME's name buffer holds a HAL name and its NUL */
typedef char hs_param_name_check[(HAL_PARAM_NAME_MAX + 1u == CS_PARAM_NAME_MAX) ? 1 : -1];

#define MEANING_MAX 200u /* characters of a parameter's meaning */

static const char *type_name(uint8_t type)
{
    switch (type) {
    case HAL_PARAM_U8: return "uint8";
    case HAL_PARAM_I16: return "int16";
    case HAL_PARAM_U16: return "uint16";
    case HAL_PARAM_I32: return "int32";
    case HAL_PARAM_U32: return "uint32";
    default: return NULL;
    }
}

/* the values type can hold (as int32) */
static void type_range(uint8_t type, int32_t *lo, int32_t *hi)
{
    switch (type) {
    case HAL_PARAM_U8: *lo = 0; *hi = 255; break;
    case HAL_PARAM_I16: *lo = -32768; *hi = 32767; break;
    case HAL_PARAM_U16: *lo = 0; *hi = 65535; break;
    case HAL_PARAM_U32: *lo = 0; *hi = INT32_MAX; break;
    default: *lo = INT32_MIN; *hi = INT32_MAX; break;
    }
}

static int is_name(const char *s)
{
    size_t n = 0;
    for (; s[n] != '\0'; n++) {
        char c = s[n];
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_'))
            return 0;
    }
    return n >= 1 && n <= HAL_PARAM_NAME_MAX;
}

static int is_meaning(const char *s)
{
    size_t n = 0;
    if (s == NULL)
        return 0;
    for (; s[n] != '\0'; n++)
        if ((unsigned char)s[n] < 0x20u || s[n] == 0x7f)
            return 0;
    return n >= 1 && n <= MEANING_MAX;
}

/* what is wrong with declaration i, or NULL */
static const char *decl_problem(size_t i)
{
    const hal_param_decl *d = &hal_param_table[i];
    int32_t lo, hi;
    size_t k;
    if (!is_name(d->name))
        return "its name is not 1 to 15 letters, digits or '_'";
    for (k = 0; k < i; k++)
        if (strcmp(hal_param_table[k].name, d->name) == 0)
            return "the name is declared twice";
    if (type_name(d->type) == NULL)
        return "its type is not one of HAL_PARAM_U8, I16, U16, I32, U32";
    type_range(d->type, &lo, &hi);
    if (d->min > d->max)
        return "its min is above its max";
    if (d->min < lo || d->max > hi)
        return "its range does not fit its type";
    if (d->def < d->min || d->def > d->max)
        return "its default is outside its range";
    if (!is_meaning(d->meaning))
        return "its meaning is not one line of 1 to 200 printable characters";
    return NULL;
}

/* Before main: `program --chainsim-params` prints the declarations and exits
 * (glibc passes argc and argv to constructors). A bad table is the
 * program's mistake: named on stderr, exit code HS_EXIT_CONFIG. */
__attribute__((constructor)) static void hs_params_listing(int argc, char **argv)
{
    size_t i;
    if (argc != 2 || argv == NULL || strcmp(argv[1], CS_PARAMS_ARG) != 0)
        return;
    for (i = 0; hal_param_table[i].name != NULL; i++) {
        const char *why = decl_problem(i);
        if (why != NULL)
            hs_die(HS_EXIT_CONFIG, "hal_param_table[%zu] (\"%s\"): %s", i,
                   hal_param_table[i].name, why);
    }
    printf("%s\n", CS_PARAMS_HEADER);
    for (i = 0; hal_param_table[i].name != NULL; i++) {
        const hal_param_decl *d = &hal_param_table[i];
        printf("%s\t%s\t%ld\t%ld\t%ld\t%s\n", d->name, type_name(d->type), (long)d->min, (long)d->max,
               (long)d->def, d->meaning);
    }
    exit(fflush(stdout) == 0 ? 0 : HS_EXIT_CONFIG);
}

static const hal_param_decl *declared(const char *name, const char *caller)
{
    size_t i;
    if (name != NULL)
        for (i = 0; hal_param_table[i].name != NULL; i++)
            if (strcmp(hal_param_table[i].name, name) == 0)
                return &hal_param_table[i];
    hs_die(HS_EXIT_CONFIG, "%s(\"%s\"): the program's hal_param_table does not declare it", caller,
           name != NULL ? name : "(null)");
}

/* the value WELCOME gave name, or NULL */
static const cs_param *given(const char *name)
{
    uint8_t i;
    for (i = 0; i < hs.n_params && i < CS_PARAMS_MAX; i++)
        if (strncmp(hs.params[i].name, name, CS_PARAM_NAME_MAX) == 0)
            return &hs.params[i];
    return NULL;
}

int32_t hal_param(const char *name)
{
    const hal_param_decl *d = declared(name, "hal_param");
    const cs_param *p;
    hs_require_init("hal_param");
    p = given(name);
    if (p == NULL)
        return d->def;
    /* the server refuses values out of range; this catches a program
     * started by hand (--attach) that declares another range */
    return p->value < d->min ? d->min : p->value > d->max ? d->max : p->value;
}

uint8_t hal_param_given(const char *name)
{
    (void)declared(name, "hal_param_given");
    hs_require_init("hal_param_given");
    return given(name) != NULL;
}

void hs_params_check(void)
{
    uint8_t i;
    size_t k;
    for (i = 0; i < hs.n_params && i < CS_PARAMS_MAX; i++) {
        for (k = 0; hal_param_table[k].name != NULL; k++)
            if (strncmp(hal_param_table[k].name, hs.params[i].name, CS_PARAM_NAME_MAX) == 0)
                break;
        if (hal_param_table[k].name == NULL)
            fprintf(stderr, "chainsim hal: warning: the scene sets parameter \"%s\", which this program does "
                            "not declare\n", hs.params[i].name);
    }
}
