/** @file
 * Named integer parameters: declared once by the program, given by the scene
 * (simulator) or compiled in (board).
 *
 * Every program defines its table, the one place a parameter's name, type,
 * range, default and meaning are written:
 *
 *     const hal_param_decl hal_param_table[] = {
 *         HAL_PARAM("release_ms", HAL_PARAM_U16, 0, 60000, 50, "low this long = released, ms"),
 *         HAL_PARAM_END
 *     };
 *
 * hal_param() gives the value clamped to the range, or the default. The
 * simulator reads the table before a run (hal-sim prints it when the program
 * is started with the argument --chainsim-params), so a scene that sets an
 * undeclared or out-of-range parameter is an error naming the key, and
 * `chainsim params PROGRAM` lists it. docs/firmware.md, "Parameters". */
#ifndef HAL_PARAM_H
#define HAL_PARAM_H

#include <stdint.h>

#define HAL_PARAM_NAME_MAX 15u /**< characters of a parameter name (the simulator's limit) */

/* the C type the program keeps the value in; the range must fit it */
#define HAL_PARAM_U8 1u  /**< kept in a uint8_t: 0..255 */
#define HAL_PARAM_I16 2u /**< kept in an int16_t: -32768..32767 */
#define HAL_PARAM_U16 3u /**< kept in a uint16_t: 0..65535 */
#define HAL_PARAM_I32 4u /**< kept in an int32_t */
#define HAL_PARAM_U32 5u /**< 0..2147483647: values travel as int32 */

/** one parameter. The board's build (HAL_PARAM_NO_TEXT) keeps only what
 * hal_param needs: the type and the meaning are for the simulator's
 * listing, and would cost flash. */
typedef struct {
    const char *name; /**< 1..HAL_PARAM_NAME_MAX letters, digits or '_'; NULL ends the table */
    int32_t min; /**< the smallest value a scene may give */
    int32_t max; /**< the largest value a scene may give */
    int32_t def; /**< the value when the scene gives none */
#ifndef HAL_PARAM_NO_TEXT
    uint8_t type;        /**< HAL_PARAM_* */
    const char *meaning; /**< one line, units included */
#endif
} hal_param_decl;

#ifdef HAL_PARAM_NO_TEXT
#define HAL_PARAM(name, type, min, max, def, meaning) { (name), (min), (max), (def) }
#define HAL_PARAM_END { 0, 0, 0, 0 }
#else
/** an entry of hal_param_table: name, HAL_PARAM_* type, range min..max, default, a line of meaning with its unit */
#define HAL_PARAM(name, type, min, max, def, meaning) { (name), (min), (max), (def), (type), (meaning) }
/** the entry that ends hal_param_table */
#define HAL_PARAM_END { 0, 0, 0, 0, 0, 0 }
#endif

/** the program's parameters, ended by HAL_PARAM_END (the program defines it) */
extern const hal_param_decl hal_param_table[];

/** Value of the declared parameter name: the scene's (or the build's) value
 * clamped to its range, else its default. A name the table does not declare
 * is a mistake in the program: hal-sim stops the program saying so, hal-pic
 * returns 0. */
int32_t hal_param(const char *name);

/** 1 when the scene (or the build) gives name a value, else 0: for a default
 * that depends on other parameters */
uint8_t hal_param_given(const char *name);

#endif
