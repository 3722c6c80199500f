/* Distributed gait rule of seed 001 (Algorithm 1, "gait generation for forward motion with
 * increased torque"). c_air[i] = 1: cell i is in the air; 0: it touches the ground.
 *   act_i = c_i AND (NOT c_{i+n1} OR NOT c_{i-n2})
 * closed = 1 (a belt): indices wrap modulo n. closed = 0 (an open strip): a neighbour outside
 * 0..n-1 does not exist and its term is false. n1 = 0 or n2 = 0 switches a term off. */
#ifndef SL_GAIT_H
#define SL_GAIT_H

#include <stdint.h>

#define SL_GAIT_MAX_CELLS 64

/* The per-cell decision: what one cell's controller computes from its own sensor and the two
 * neighbour readings it received (-1 = that neighbour does not exist). */
uint8_t sl_gait_cell(uint8_t c_self, int8_t c_ahead, int8_t c_behind);

/* Neighbour reading of cell i at offset off (+n1 ahead, -n2 behind): 0/1, or -1 if absent. */
int8_t sl_gait_neighbour(const uint8_t *c_air, uint8_t n, uint8_t i, int16_t off, uint8_t closed);

/* The whole chain, one snapshot: bit-packed masks (bit i of byte i/8 = cell i), n <= 64. */
void sl_gait_step(const uint8_t *air_mask, uint8_t n, uint8_t n1, uint8_t n2, uint8_t closed, uint8_t *act_mask);

#endif
