/* Helpers of the chain command set (chain_commands.h). */
#include "chain_commands.h"

void cc_put_i16(uint8_t *p, int16_t v)
{
    uint16_t u = (uint16_t)v;
    p[0] = (uint8_t)(u & 0xFFu);
    p[1] = (uint8_t)(u >> 8);
}

int16_t cc_get_i16(const uint8_t *p)
{
    uint16_t u = (uint16_t)((uint16_t)p[0] | ((uint16_t)p[1] << 8));
    return (int16_t)u;
}

char cc_type_letter(uint8_t type)
{
    switch (type) {
    case MT_ROTATION: return 'R';
    case MT_HELICOIDAL: return 'H';
    case MT_SUPPORT: return 'S';
    case MT_EXTENSION: return 'E';
    case MT_TOUCH: return 'T';
    case MT_TRAVELLER: return 'W';
    case MT_PASSIVE: return 'P';
    default: return '?';
    }
}
