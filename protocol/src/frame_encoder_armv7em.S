@ The frame encoder's word loop for ARMv7E-M (Cortex-M4/M7): CRC-32 slicing by 4 and COBS over
@ whole words, the DSP extension's byte-wise add (UADD8) flagging a word's non-zero bytes.
@ Same contract and output as the portable loop in frame_encoder.cc (CTest and the mps2 framing
@ check compare both against CRC-then-COBS); hand-scheduled because the compiler's version spent
@ a third more instructions on a telemetry frame.
  .syntax unified
  .arch armv7e-m
  .thumb
  .text

@ void palpa_frame_words_v7em(FrameWords* state, const uint8_t* words_end,
@                             const uint32_t* crc_tables, const WordCodes* codes_by_nonzero);
@ FrameWords { const uint8_t* in; uint8_t* dst; uint8_t* code_at; uint32_t crc; } (crc inverted)
@ Runs while in != words_end (a whole number of words); returns early after a zero-free word
@ that leaves the open block longer than 250 bytes (the caller finishes byte by byte, which
@ splits 254-byte blocks).
@ One word: CRC, copy, codes. Falls through when done (a word with a zero without a branch); a
@ zero-free word that leaves the open block longer than 250 bytes ends the loop.
  .macro WORD
  ldr     r10, [r0], #4           @ the next four packet bytes
  eor     r4, r4, r10             @ CRC: fold the word in, four table lookups
  uxtb    r12, r4
  ldr     r12, [r8, r12, lsl #2]
  ubfx    lr, r4, #8, #8
  ldr     lr, [r7, lr, lsl #2]
  eor     r12, r12, lr
  ubfx    lr, r4, #16, #8
  ldr     lr, [r6, lr, lsl #2]
  eor     r12, r12, lr
  lsr     lr, r4, #24
  ldr     lr, [r5, lr, lsl #2]
  eor     r4, r12, lr
  uadd8   r12, r10, r11           @ GE[k] set when byte k is not zero
  mrs     r12, apsr
  ubfx    r12, r12, #16, #4       @ the non-zero pattern
  cmp     r12, #15
  beq     .Lno_zero\@
  add     r12, r9, r12, lsl #3
  ldrd    r12, lr, [r12]          @ r12: code bytes for the inner zeros; lr: first | last << 8,
  orr     r10, r10, r12           @ signed offsets from the word's end
  str     r10, [r2], #4           @ the word, its inner zeros replaced by their codes
  sxtab   r12, r2, lr             @ the first zero closes the open block ...
  sub     r10, r12, r3
  strb    r10, [r3]
  sxtab   r3, r2, lr, ror #8      @ ... and the last one opens a new block
.Lword_done\@:
  .subsection 1                   @ out of line: telemetry words mostly hold a zero
.Lno_zero\@:
  str     r10, [r2], #4
  sub     r12, r2, r3             @ only a zero-free word lengthens the open block
  cmp     r12, #250
  bgt     .Ldone
  b       .Lword_done\@
  .subsection 0
  .endm

  .global palpa_frame_words_v7em
  .type palpa_frame_words_v7em, %function
  .thumb_func
palpa_frame_words_v7em:
  push    {r0, r4-r11, lr}
  mov     r9, r3                  @ codes, 8 bytes per non-zero pattern: inner codes, first, last
  mov     r5, r2                  @ CRC table 0
  add     r6, r2, #1024           @ table 1
  add     r7, r2, #2048           @ table 2
  add     r8, r2, #3072           @ table 3
  ldm     r0, {r0, r2, r3, r4}    @ in, dst, code_at, crc
  mvn     r11, #0                 @ 0xFFFFFFFF: byte + 0xFF carries exactly when the byte is not 0
  sub     r12, r1, r0
  tst     r12, #4                 @ an odd number of words: one first, then pairs
  beq     .Lpairs
  WORD
.Lpairs:
  cmp     r0, r1
  beq     .Ldone
.Lloop:                           @ two words per pass: one end check per pair
  WORD
  WORD
  cmp     r0, r1
  bne     .Lloop
.Ldone:
  pop     {r12}
  stm     r12, {r0, r2, r3, r4}
  pop     {r4-r11, pc}
  .size palpa_frame_words_v7em, . - palpa_frame_words_v7em
