@ The PI step's play-operator pass for ARMv7E-M (Cortex-M4/M7), hand-scheduled: two operators per
@ word, 21 instructions a pair. Same contract and results as PlayPairsPortable (play_pairs.cc);
@ the mps2 compensator check compares the two on the target.
  .syntax unified
  .arch armv7e-m
  .thumb
  .text

@ int32_t palpa_play_pairs_v7em(const PlayPair* end, uint32_t* memory_end, const PlayPair* begin,
@                               uint32_t shift, int32_t later);
@ PlayPair: cumulative, weight, inverse_threshold, negative_inverse_threshold, inverse_weight,
@ threshold, negative_threshold (7 words). At least one pair.
  .global palpa_play_pairs_v7em
  .type palpa_play_pairs_v7em, %function
  .thumb_func
palpa_play_pairs_v7em:
  push    {r4-r11, lr}
  ldr     r4, [sp, #36]           @ later: W_n a - v + the higher operators' w_j c_j
  movs    r5, #0                  @ the inverse states' weighted sum
.Lpair:
  ldr     r6, [r1, #-4]!          @ two forward states, relative to the last applied drive
  ldmdb   r0!, {r7, r8}           @ r, -r
  qadd16  r6, r6, r3              @ relative to this drive (saturated: beyond ±r either way)
  ssub16  r9, r6, r7              @ GE where c >= r ...
  sel     r6, r7, r6              @ ... take r
  sadd16  r9, r6, r7              @ GE where c >= -r ...
  sel     r6, r6, r8              @ ... keep c, else -r
  str     r6, [r1]
  ldmdb   r0!, {r9-r12, lr}       @ W, w, r', -r', w'
  smlatt  r7, r6, r9, r4          @ upper operator's inverse state
  smlatt  r4, r6, r10, r4
  smlabb  r8, r6, r9, r4          @ lower operator's
  smlabb  r4, r6, r10, r4
  pkhtb   r7, r7, r8, asr #16     @ both states' upper halves in one word
  ssub16  r8, r7, r11             @ clamped to ±r'
  sel     r7, r11, r7
  sadd16  r8, r7, r11
  sel     r7, r7, r12
  smlad   r5, r7, lr, r5          @ weighted into the sum
  cmp     r0, r2
  bne     .Lpair
  mov     r0, r5
  pop     {r4-r11, pc}
  .size palpa_play_pairs_v7em, .-palpa_play_pairs_v7em
