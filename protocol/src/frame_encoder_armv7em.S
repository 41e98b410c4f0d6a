@ The frame encoder's word loop for ARMv7E-M (Cortex-M4/M7): CRC-32 slicing by 4 and COBS over
@ whole words, the DSP extension's byte-wise subtract (USUB8) flagging a word's zero bytes.
@ Same contract and output as the portable loop in frame_encoder.cc (CTest and the mps2 framing
@ check compare both against CRC-then-COBS); hand-scheduled because the compiler's version spent
@ a third more instructions on a telemetry frame.
  .syntax unified
  .arch armv7e-m
  .thumb
  .text

@ uint8_t* palpa_frame_v7em(FrameWords* state, uint8_t* packet_end,
@                           const uint32_t* crc_tables, const WordCodes* codes);
@ FrameWords { const uint8_t* in; uint8_t* dst; uint8_t* code_at; uint32_t crc; } (crc inverted)
@ Encodes the frame from state->in to packet_end, appends the CRC after the packet, COBS-codes it
@ and writes the delimiter; returns the end of the frame. Returns 0, with *state saying where it
@ stopped, when a block could fill up (a zero-free run of about 250 bytes): the caller finishes
@ byte by byte, which splits 254-byte blocks.

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
  usub8   r12, r11, r10           @ GE[k] set when 0 - byte k does not borrow: byte k is zero
  mrs     r12, apsr
  ands    r12, r12, #0xF0000      @ the zero pattern, in bits 16..19
  beq     .Lno_zero\@
  add     r12, r9, r12, lsr #13   @ its entry: 8 bytes per pattern
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
  bgt     .Lstopped
  b       .Lword_done\@
  .subsection 0
  .endm

  .global palpa_frame_v7em
  .type palpa_frame_v7em, %function
  .thumb_func
palpa_frame_v7em:
  push    {r0, r1, r4-r11, lr}
  mov     r9, r3                  @ codes, 8 bytes per zero pattern: inner codes, first, last
  mov     r5, r2                  @ CRC table 0
  add     r6, r2, #1024           @ table 1
  add     r7, r2, #2048           @ table 2
  add     r8, r2, #3072           @ table 3
  ldm     r0, {r0, r2, r3, r4}    @ in, dst, code_at, crc
  sub     r12, r1, r0
  bic     r12, r12, #3
  add     r1, r0, r12             @ the end of the packet's whole words
  mov     r11, #0
  tst     r12, #4                 @ the odd word, then a pair, then four words per pass
  beq     .Lpair
  WORD
.Lpair:
  sub     r12, r1, r0             @ (a word clobbers r12)
  tst     r12, #8
  beq     .Lquads
  WORD
  WORD
.Lquads:
  cmp     r0, r1
  beq     .Lwords_done
.Lloop:                           @ one end check per four words
  WORD
  WORD
  WORD
  WORD
  cmp     r0, r1
  bne     .Lloop
.Lwords_done:
  sub     r12, r2, r3             @ up to seven more bytes could fill the open block
  cmp     r12, #247
  bgt     .Lstopped
  ldr     r1, [sp, #4]            @ packet_end
  mov     r10, r0                 @ the tail's COBS starts here
  cmp     r0, r1
  beq     .Lcrc_done
.Lcrc_byte:                       @ the last one to three packet bytes into the CRC
  ldrb    r12, [r0], #1
  eor     r12, r12, r4
  uxtb    r12, r12
  ldr     r12, [r5, r12, lsl #2]
  eor     r4, r12, r4, lsr #8
  cmp     r0, r1
  bne     .Lcrc_byte
.Lcrc_done:
  mvn     r4, r4
  str     r4, [r1], #4            @ the CRC, little-endian, after the packet; r1: end of input
  ldr     r6, [r10], #4           @ the tail's first word (a table base no longer needed)
  usub8   r12, r11, r6
  mrs     r12, apsr
  ands    r12, r12, #0xF0000
  beq     .Ltail_no_zero
  add     r12, r9, r12, lsr #13
  ldrd    r12, lr, [r12]
  orr     r6, r6, r12
  str     r6, [r2], #4
  sxtab   r12, r2, lr
  sub     r6, r12, r3
  strb    r6, [r3]
  sxtab   r3, r2, lr, ror #8
  b       .Ltail_bytes
.Ltail_no_zero:
  str     r6, [r2], #4
.Ltail_bytes:                     @ zero to three bytes left
  cmp     r10, r1
  beq     .Lclose
  ldrb    r6, [r10], #1
  cbz     r6, .Ltail_zero
  strb    r6, [r2], #1
  b       .Ltail_bytes
.Ltail_zero:
  sub     r12, r2, r3             @ a zero closes the block where it stands
  strb    r12, [r3]
  mov     r3, r2
  add     r2, r2, #1
  b       .Ltail_bytes
.Lclose:
  sub     r12, r2, r3
  strb    r12, [r3]               @ the last block's code
  strb    r11, [r2], #1           @ the delimiter
  mov     r0, r2
  add     sp, sp, #8
  pop     {r4-r11, pc}
.Lstopped:
  pop     {r12}
  stm     r12, {r0, r2, r3, r4}
  mov     r0, #0
  add     sp, sp, #4
  pop     {r4-r11, pc}
  .size palpa_frame_v7em, . - palpa_frame_v7em
