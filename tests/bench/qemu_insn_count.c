// QEMU TCG plugin: counts guest instructions executed inside call spans (entry → return site).
//
// Debian's QEMU exports the plugin API but ships no qemu-plugin.h, so the few functions used here
// are declared below (QEMU 7.2, plugin API version 1). Arguments, one per span:
//   span=NAME:ENTRY:RET[:RET...]   hexadecimal addresses of the function's first instruction and
//                                  of every instruction following a call to it
//   exclude=NAME                   the span NAME is not part of the control tick: the plugin
//                                  also reports "control", each tick minus the excluded spans
// The span named "tick" is the frame: every other span also reports its sum per tick. Spans are
// inclusive (callees and interrupts taken inside count). Counts are exact per instruction and,
// under -icount, identical run after run. The report is printed at exit (-d plugin).
#include <inttypes.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef uint64_t qemu_plugin_id_t;
typedef struct qemu_info_t qemu_info_t;
struct qemu_plugin_tb;
struct qemu_plugin_insn;
enum qemu_plugin_cb_flags { QEMU_PLUGIN_CB_NO_REGS };
enum qemu_plugin_op { QEMU_PLUGIN_INLINE_ADD_U64 };

#define PLUGIN_EXPORT __attribute__((visibility("default")))
PLUGIN_EXPORT int qemu_plugin_version = 1;

void qemu_plugin_register_vcpu_tb_trans_cb(qemu_plugin_id_t id,
                                           void (*cb)(qemu_plugin_id_t, struct qemu_plugin_tb*));
size_t qemu_plugin_tb_n_insns(const struct qemu_plugin_tb* tb);
struct qemu_plugin_insn* qemu_plugin_tb_get_insn(const struct qemu_plugin_tb* tb, size_t idx);
uint64_t qemu_plugin_insn_vaddr(const struct qemu_plugin_insn* insn);
void qemu_plugin_register_vcpu_insn_exec_inline(struct qemu_plugin_insn* insn,
                                                enum qemu_plugin_op op, void* ptr, uint64_t imm);
void qemu_plugin_register_vcpu_insn_exec_cb(struct qemu_plugin_insn* insn,
                                            void (*cb)(unsigned int vcpu_index, void* userdata),
                                            enum qemu_plugin_cb_flags flags, void* userdata);
void qemu_plugin_register_atexit_cb(qemu_plugin_id_t id, void (*cb)(qemu_plugin_id_t, void*),
                                    void* userdata);
void qemu_plugin_outs(const char* string);

enum { kMaxSpans = 16, kMaxReturns = 32 };

typedef struct {
  char name[40];
  uint64_t entry;
  uint64_t returns[kMaxReturns];
  int return_count;
  int depth;       // > 0 while inside the span (nested calls count once)
  uint64_t start;  // instruction count at entry
  uint64_t calls;
  uint64_t total;
  uint64_t max_call;
  uint64_t this_tick;  // sum inside the current tick
  uint64_t max_tick;
  int excluded;  // not part of the control tick
} Span;

static Span spans[kMaxSpans];
static int span_count;
static Span* tick_span;
static uint64_t executed;  // every guest instruction, incremented inline
static uint64_t ticks;
static int exclusions;          // spans named by exclude=
static uint64_t control_total;  // tick minus the excluded spans, summed over ticks
static uint64_t control_max;

static void OnEntry(unsigned int vcpu, void* userdata) {
  (void)vcpu;
  Span* s = userdata;
  if (s->depth++ == 0) s->start = executed;
}

static void OnReturn(unsigned int vcpu, void* userdata) {
  (void)vcpu;
  Span* s = userdata;
  if (s->depth == 0) return;  // a return site reached without the call (another path)
  if (--s->depth != 0) return;
  const uint64_t n = executed - s->start;
  s->calls++;
  s->total += n;
  if (n > s->max_call) s->max_call = n;
  if (s == tick_span) {
    ticks++;
    uint64_t control = n;
    for (int i = 0; i < span_count; ++i) {
      if (spans[i].excluded) control -= spans[i].this_tick;
    }
    control_total += control;
    if (control > control_max) control_max = control;
    for (int i = 0; i < span_count; ++i) {
      Span* other = &spans[i];
      if (other->this_tick > other->max_tick) other->max_tick = other->this_tick;
      other->this_tick = 0;
    }
  } else if (tick_span != NULL && tick_span->depth > 0) {
    s->this_tick += n;
  }
}

static void OnTranslate(qemu_plugin_id_t id, struct qemu_plugin_tb* tb) {
  (void)id;
  const size_t n = qemu_plugin_tb_n_insns(tb);
  for (size_t i = 0; i < n; ++i) {
    struct qemu_plugin_insn* insn = qemu_plugin_tb_get_insn(tb, i);
    const uint64_t pc = qemu_plugin_insn_vaddr(insn);
    // Callbacks first, so a span's own first instruction is inside it and its return site is not.
    for (int s = 0; s < span_count; ++s) {
      for (int r = 0; r < spans[s].return_count; ++r) {
        if (spans[s].returns[r] == pc) {
          qemu_plugin_register_vcpu_insn_exec_cb(insn, OnReturn, QEMU_PLUGIN_CB_NO_REGS, &spans[s]);
        }
      }
      if (spans[s].entry == pc)
        qemu_plugin_register_vcpu_insn_exec_cb(insn, OnEntry, QEMU_PLUGIN_CB_NO_REGS, &spans[s]);
    }
    qemu_plugin_register_vcpu_insn_exec_inline(insn, QEMU_PLUGIN_INLINE_ADD_U64, &executed, 1);
  }
}

static void OnExit(qemu_plugin_id_t id, void* userdata) {
  (void)id;
  (void)userdata;
  char line[512];
  snprintf(line, sizeof(line), "insn-count: executed %" PRIu64 " ticks %" PRIu64 "\n", executed,
           ticks);
  qemu_plugin_outs(line);
  for (int i = 0; i < span_count; ++i) {
    const Span* s = &spans[i];
    const double mean_call = s->calls ? (double)s->total / (double)s->calls : 0.0;
    const double mean_tick = ticks ? (double)s->total / (double)ticks : 0.0;
    snprintf(line, sizeof(line),
             "insn-count: span %.39s calls %" PRIu64 " mean_call %.1f max_call %" PRIu64
             " mean_tick %.1f max_tick %" PRIu64 "\n",
             s->name, s->calls, mean_call, s->max_call, mean_tick,
             s == tick_span ? s->max_call : s->max_tick);
    qemu_plugin_outs(line);
  }
  if (exclusions > 0 && ticks > 0) {
    snprintf(line, sizeof(line), "insn-count: control mean_tick %.1f max_tick %" PRIu64 "\n",
             (double)control_total / (double)ticks, control_max);
    qemu_plugin_outs(line);
  }
}

// Marks "exclude=NAME" (a span given before it); returns 0 on success.
static int ParseExclude(const char* arg) {
  if (strncmp(arg, "exclude=", 8) != 0) return -1;
  for (int i = 0; i < span_count; ++i) {
    if (strcmp(spans[i].name, arg + 8) == 0 && &spans[i] != tick_span) {
      spans[i].excluded = 1;
      exclusions++;
      return 0;
    }
  }
  return -1;
}

// Parses "span=NAME:ENTRY:RET[:RET...]"; returns 0 on success.
static int ParseSpan(const char* arg) {
  if (strncmp(arg, "span=", 5) != 0 || span_count == kMaxSpans) return -1;
  Span* s = &spans[span_count];
  const char* p = arg + 5;
  const char* colon = strchr(p, ':');
  if (colon == NULL || colon == p || (size_t)(colon - p) >= sizeof(s->name)) return -1;
  memcpy(s->name, p, (size_t)(colon - p));
  p = colon + 1;
  char* end;
  s->entry = strtoull(p, &end, 16);
  if (end == p) return -1;
  while (*end == ':' && s->return_count < kMaxReturns) {
    p = end + 1;
    s->returns[s->return_count] = strtoull(p, &end, 16);
    if (end == p) return -1;
    s->return_count++;
  }
  if (*end != '\0' || s->return_count == 0) return -1;
  if (strcmp(s->name, "tick") == 0) tick_span = s;
  span_count++;
  return 0;
}

PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t* info, int argc,
                                      char** argv) {
  (void)info;
  for (int i = 0; i < argc; ++i) {
    if (ParseSpan(argv[i]) != 0 && ParseExclude(argv[i]) != 0) {
      fprintf(stderr,
              "qemu_insn_count: bad argument '%s' (want span=NAME:ENTRY:RET[:RET...], hex, at most "
              "16 spans of 32 return sites, or exclude=NAME of a span given before it)\n",
              argv[i]);
      return -1;
    }
  }
  qemu_plugin_register_vcpu_tb_trans_cb(id, OnTranslate);
  qemu_plugin_register_atexit_cb(id, OnExit, NULL);
  return 0;
}
