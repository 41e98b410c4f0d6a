@ The PI step's play-operator pass for ARMv7E-M (Cortex-M4/M7), hand-scheduled: two operators per
@ word, 17 instructions a pair (the loop unrolled twice). Same contract and results as
@ PlayPairsPortable (play_pairs.cc); the mps2 play check compares the two on the target.
@
@ The drive moves one way per step, so each forward operator only needs the clamp on that side
@ (two instructions instead of four): one loop for a rising drive, one for a falling one. The
@ lower operator's inverse state takes one SMLAD (W_2k c_2k + w_2k+1 c_2k+1 from the `mixed`
@ word), and what both add to the states below another.
  .syntax unified
  .arch armv7e-m
  .thumb
  .text

@ int32_t palpa_play_pairs_v7em(const PlayPair* end, uint32_t* memory_end, const PlayPair* begin,
@                               uint32_t shift, int32_t later);
@ PlayPair: cumulative, mixed, weight, inverse_threshold, negative_inverse_threshold,
@ inverse_weight, threshold, negative_threshold (8 words, 32 bytes). At least one pair.
@
@ Registers: r0 pair (walks down), r1 memory (walks down), r2 begin, r3 shift, r4 later,
@ r5 the inverse states' weighted sum, r6 c, r7-r12 and lr scratch.

@ The inverse half of a pair, the same in both loops: the two states from `later` (r4) and c (r6),
@ their upper halves clamped to ±r', weighted into r5.
  .macro inverse_pair
  ldmdb   r0!, {r7-r12}           @ W, mixed, w, r', -r', w'
  smlatt  r7, r6, r7, r4          @ upper operator's state: later + W c
  smlad   r8, r6, r8, r4          @ lower operator's: later + w_upper c_upper + W c
  smlad   r4, r6, r9, r4          @ later gains both w c
  pkhtb   r7, r7, r8, asr #16     @ both states' upper halves in one word
  ssub16  r9, r7, r10             @ GE where s >= r' ...
  sel     r7, r10, r7             @ ... take r'
  sadd16  r9, r7, r10             @ GE where s >= -r' ...
  sel     r7, r7, r11             @ ... keep s, else -r'
  smlad   r5, r7, r12, r5         @ weighted into the sum
  .endm

@ Rising drive: c = min(c + shift, r).
  .macro rising_pair
  ldr     r6, [r1, #-4]!          @ two forward states, relative to the last applied drive
  ldmdb   r0!, {r7, r8}           @ r, -r
  qadd16  r6, r6, r3              @ relative to this drive (saturated)
  ssub16  r9, r6, r7              @ GE where c >= r ...
  sel     r6, r7, r6              @ ... take r
  str     r6, [r1]
  inverse_pair
  .endm

@ Falling drive: c = max(c + shift, -r).
  .macro falling_pair
  ldr     r6, [r1, #-4]!
  ldmdb   r0!, {r7, r8}           @ r, -r
  qadd16  r6, r6, r3
  sadd16  r9, r6, r7              @ GE where c >= -r ...
  sel     r6, r6, r8              @ ... keep c, else -r
  str     r6, [r1]
  inverse_pair
  .endm

  .global palpa_play_pairs_v7em
  .type palpa_play_pairs_v7em, %function
  .thumb_func
palpa_play_pairs_v7em:
  push    {r4-r11, lr}
  ldr     r4, [sp, #36]           @ later: W_n a - v + the higher operators' w_j c_j
  movs    r5, #0
  sub     ip, r0, r2              @ 32 bytes a pair: bit 5 set for an odd count
  cmp     r3, #0                  @ the sign of the drive's change (the high lane)
  blt     .Lfalling
  tst     ip, #32
  bne     .Lrising_odd
.Lrising:
  rising_pair
.Lrising_odd:
  rising_pair
  cmp     r0, r2
  bne     .Lrising
  mov     r0, r5
  pop     {r4-r11, pc}
.Lfalling:
  tst     ip, #32
  bne     .Lfalling_odd
.Lfalling_loop:
  falling_pair
.Lfalling_odd:
  falling_pair
  cmp     r0, r2
  bne     .Lfalling_loop
  mov     r0, r5
  pop     {r4-r11, pc}
  .size palpa_play_pairs_v7em, .-palpa_play_pairs_v7em
