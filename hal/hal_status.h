/** @file
 * Status codes shared by every HAL call that can fail. */
#ifndef HAL_STATUS_H
#define HAL_STATUS_H

#include <stdint.h>

/** what a HAL call that can fail returns: HAL_OK, HAL_EMPTY or a negative HAL_ERR_* */
typedef int8_t hal_status;

#define HAL_OK 0          /**< done */
#define HAL_EMPTY 1       /**< nothing to read (not an error) */
#define HAL_ERR_ARG (-1)  /**< an argument is out of range */
#define HAL_ERR_FULL (-2) /**< an output queue is full this tick; try after the next wait */

#endif
