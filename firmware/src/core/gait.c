#include "gait.h"

uint8_t sl_gait_cell(uint8_t c_self, int8_t c_ahead, int8_t c_behind)
{
    return (uint8_t)(c_self == 1 && (c_ahead == 0 || c_behind == 0));
}

int8_t sl_gait_neighbour(const uint8_t *c_air, uint8_t n, uint8_t i, int16_t off, uint8_t closed)
{
    if (off == 0)
        return (int8_t)c_air[i]; /* n = 0: the cell itself (in the air whenever it may fire) */
    int16_t j = (int16_t)i + off;
    if (closed) {
        j %= (int16_t)n;
        if (j < 0)
            j += n;
    } else if (j < 0 || j >= n) {
        return -1;
    }
    return (int8_t)c_air[j];
}

void sl_gait_step(const uint8_t *air_mask, uint8_t n, uint8_t n1, uint8_t n2, uint8_t closed, uint8_t *act_mask)
{
    uint8_t c[SL_GAIT_MAX_CELLS];
    if (n > SL_GAIT_MAX_CELLS)
        n = SL_GAIT_MAX_CELLS;
    for (uint8_t i = 0; i < n; i++)
        c[i] = (uint8_t)((air_mask[i >> 3] >> (i & 7)) & 1);
    for (uint8_t b = 0; b < (uint8_t)((n + 7) / 8); b++)
        act_mask[b] = 0;
    for (uint8_t i = 0; i < n; i++) {
        int8_t ahead = sl_gait_neighbour(c, n, i, (int16_t)n1, closed);
        int8_t behind = sl_gait_neighbour(c, n, i, -(int16_t)n2, closed);
        if (sl_gait_cell(c[i], ahead, behind))
            act_mask[i >> 3] |= (uint8_t)(1u << (i & 7));
    }
}
