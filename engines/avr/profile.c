/* The engine's report (see profile.h): counters kept as the chip runs, JSON written on request. */
#define _GNU_SOURCE
#include "profile.h"

#include <fcntl.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <sim_avr.h>
#include <sim_elf.h>
#include <sim_interrupts.h>

#include "engine.h"

uint64_t avr_profile_pc_cycles[AVR_PROFILE_WORDS];

static int report_fd = -1;
static uint64_t sleep_cycles;

struct vector_stats {
  uint64_t entries, cycles;
  uint64_t latency_min, latency_max, latency_sum;
  uint64_t pending_since, started;
  int pending, running;
};
static struct vector_stats vectors[64];

struct symbol {
  uint32_t addr;
  const char *name;
};
static struct symbol *symbols;
static uint32_t symbol_count;

/* The longest stretch with interrupts held off (an ISR's whole run, or code between CLI and SEI):
 * what bounds every interrupt's latency, so it names the code to look at when bytes overrun. */
static struct {
  int off;
  uint64_t since;
  uint32_t pc;
  uint64_t longest, longest_at;
  uint32_t longest_pc;
} irq_off;

/* The ATmega2560's vector table: 57 vectors of one 2-word JMP each from address 0 (datasheet
 * table 14-1); the chip enters an interrupt there. */
enum { VECTOR_BYTES = 4, VECTORS = 57 };

void avr_profile_interrupts_flag(int on, uint32_t pc, uint64_t cycle) {
  /* From a reset to the first SEI no interrupt is enabled yet that could wait: not counted. */
  if (!on && pc == 0) {
    irq_off.off = 0;
    return;
  }
  if (!on && !irq_off.off) {
    irq_off.off = 1;
    irq_off.since = cycle;
    irq_off.pc = pc;
  } else if (on && irq_off.off) {
    irq_off.off = 0;
    if (cycle - irq_off.since > irq_off.longest) {
      irq_off.longest = cycle - irq_off.since;
      irq_off.longest_at = irq_off.since;
      irq_off.longest_pc = irq_off.pc;
    }
  }
}

/* "__vector_N" for a vector slot, else the function holding pc and the offset into it. */
static void code_name(uint32_t pc, char *out, size_t size) {
  if (pc < VECTOR_BYTES * VECTORS) {
    snprintf(out, size, "__vector_%u", (unsigned)(pc / VECTOR_BYTES));
    return;
  }
  const struct symbol *at = NULL;
  for (uint32_t lo = 0, hi = symbol_count; lo < hi;) { /* the last symbol at or below pc */
    const uint32_t mid = lo + (hi - lo) / 2;
    if (symbols[mid].addr <= pc) {
      at = &symbols[mid];
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  if (at) snprintf(out, size, "%s+0x%x", at->name, (unsigned)(pc - at->addr));
  else snprintf(out, size, "0x%05x", (unsigned)pc);
}

static void on_pending(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq;
  struct vector_stats *v = &vectors[(uintptr_t)param];
  if (value && !v->pending) v->pending_since = engine.avr->cycle;
  v->pending = value != 0;
}

static void on_running(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq;
  struct vector_stats *v = &vectors[(uintptr_t)param];
  const uint64_t now = engine.avr->cycle;
  if (value) {
    const uint64_t latency = now - v->pending_since;
    if (!v->entries || latency < v->latency_min) v->latency_min = latency;
    if (latency > v->latency_max) v->latency_max = latency;
    v->latency_sum += latency;
    v->entries++;
    v->started = now;
    v->running = 1;
  } else if (v->running) {
    v->cycles += now - v->started; /* inclusive of any interrupt nested in it */
    v->running = 0;
  }
}

static int by_address(const void *a, const void *b) {
  const struct symbol *x = a, *y = b;
  return x->addr < y->addr ? -1 : x->addr > y->addr;
}

void avr_profile_init(const char *path, const struct elf_firmware_t *firmware) {
  avr_t *avr = engine.avr;
  if ((avr->flashend + 1) / 2 != AVR_PROFILE_WORDS)
    engine_fatal("the engine's profile counts an ATmega2560's %u flash words; this MCU has %u", AVR_PROFILE_WORDS,
                 (unsigned)(avr->flashend + 1) / 2);
  for (uint8_t i = 0; i < avr->interrupts.vector_count; ++i) {
    avr_int_vector_t *v = avr->interrupts.vector[i];
    if (!v || v->vector >= 64) continue;
    avr_irq_register_notify(v->irq + AVR_INT_IRQ_PENDING, on_pending, (void *)(uintptr_t)v->vector);
    avr_irq_register_notify(v->irq + AVR_INT_IRQ_RUNNING, on_running, (void *)(uintptr_t)v->vector);
  }
  /* Code symbols only: data lives at 0x800000 and up in an AVR ELF. */
  symbols = calloc(firmware->symbolcount + 1, sizeof *symbols);
  for (uint32_t i = 0; symbols && i < firmware->symbolcount; ++i) {
    const avr_symbol_t *s = firmware->symbol[i];
    /* Linker-made constants (__TEXT_REGION_ORIGIN__ and the like) name no code. */
    const size_t len = s ? strlen(s->symbol) : 0;
    const int linker_constant = len > 4 && strncmp(s->symbol, "__", 2) == 0 && strcmp(s->symbol + len - 2, "__") == 0;
    if (s && s->addr < 0x800000u && len && s->symbol[0] != '.' && !linker_constant)
      symbols[symbol_count++] = (struct symbol){s->addr, s->symbol};
  }
  if (symbols) qsort(symbols, symbol_count, sizeof *symbols, by_address);
  if (path) {
    report_fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (report_fd < 0) engine_fatal("cannot write the engine's report %s", path);
  }
}

/* The words the report counts: the code simavr loaded, without the .data image after it. */
static uint32_t counted_words(void) {
  const avr_t *avr = engine.avr;
  return avr->codeend / 2 + 1 < AVR_PROFILE_WORDS ? avr->codeend / 2 + 1 : AVR_PROFILE_WORDS;
}

void avr_profile_symbol_words(uint32_t word, uint32_t *lo, uint32_t *hi) {
  const uint32_t counted = counted_words();
  if (word >= counted) { /* counted by no symbol */
    *lo = counted;
    *hi = UINT32_MAX;
    return;
  }
  *lo = 0;
  *hi = counted;
  for (uint32_t a = 0, b = symbol_count; a < b;) { /* the first symbol past word */
    const uint32_t mid = a + (b - a) / 2;
    if (symbols[mid].addr / 2 <= word) {
      *lo = symbols[mid].addr / 2;
      a = mid + 1;
    } else {
      if (symbols[mid].addr / 2 < *hi) *hi = symbols[mid].addr / 2;
      b = mid;
    }
  }
}

void avr_profile_sleep(uint64_t cycles) { sleep_cycles += cycles; }

uint64_t avr_profile_busy_cycles(void) {
  return engine.avr->cycle > sleep_cycles ? engine.avr->cycle - sleep_cycles : 0;
}

struct function_total {
  const char *name;
  uint64_t cycles;
};

void avr_profile_write(void) {
  if (report_fd < 0) return;
  static char text[16384];
  size_t n = 0;
#define OUT(...) n += (size_t)snprintf(text + n, n < sizeof text ? sizeof text - n : 0, __VA_ARGS__)
  const avr_t *avr = engine.avr;
  const uint64_t cycles = avr->cycle;
  const uint64_t busy = avr_profile_busy_cycles();
  OUT("{\n  \"engine\": \"avr\",\n  \"clock_hz\": %" PRIu64 ",\n  \"cycles\": %" PRIu64 ",\n  \"busy_cycles\": %" PRIu64
      ",\n  \"cpu_load\": %.6f,\n  \"isrs\": [",
      engine.clock_hz, cycles, busy, cycles ? (double)busy / (double)cycles : 0.0);
  int first = 1;
  for (int i = 0; i < 64; ++i) {
    const struct vector_stats *v = &vectors[i];
    if (!v->entries) continue;
    OUT("%s\n    {\"vector\": %d, \"symbol\": \"__vector_%d\", \"entries\": %" PRIu64 ", \"cycles\": %" PRIu64
        ", \"load\": %.6f, \"latency_cycles\": {\"min\": %" PRIu64 ", \"mean\": %.3f, \"max\": %" PRIu64 "}}",
        first ? "" : ",", i, i, v->entries, v->cycles, cycles ? (double)v->cycles / (double)cycles : 0.0,
        v->latency_min, (double)v->latency_sum / (double)v->entries, v->latency_max);
    first = 0;
  }
  OUT("%s],\n  \"top_functions\": [", first ? "" : "\n  ");
  /* Each code word's cycles go to the symbol at or below it. */
  enum { TOP = 10 };
  struct function_total top[TOP];
  int tops = 0;
  const uint32_t code_words = counted_words();
  for (uint32_t s = 0; s < symbol_count; ++s) {
    if (s + 1 < symbol_count && symbols[s + 1].addr == symbols[s].addr) continue; /* aliases: the last name */
    const uint32_t from = symbols[s].addr / 2;
    uint32_t to = s + 1 < symbol_count ? symbols[s + 1].addr / 2 : code_words;
    if (to > code_words) to = code_words;
    uint64_t sum = 0;
    for (uint32_t w = from; w < to; ++w) sum += avr_profile_pc_cycles[w];
    if (!sum) continue;
    int at;
    if (tops < TOP) at = tops++;
    else if (top[TOP - 1].cycles >= sum) continue; /* not among the top ones */
    else at = TOP - 1;
    top[at] = (struct function_total){symbols[s].name, sum};
    while (at > 0 && top[at - 1].cycles < top[at].cycles) {
      const struct function_total t = top[at - 1];
      top[at - 1] = top[at];
      top[at] = t;
      --at;
    }
  }
  for (int i = 0; i < tops; ++i)
    OUT("%s\n    {\"name\": \"%s\", \"cycles\": %" PRIu64 ", \"share\": %.6f}", i ? "," : "", top[i].name, top[i].cycles,
        busy ? (double)top[i].cycles / (double)busy : 0.0);
  /* A stretch still open counts as far as it has gone. */
  uint64_t longest = irq_off.longest, longest_at = irq_off.longest_at;
  uint32_t longest_pc = irq_off.longest_pc;
  if (irq_off.off && cycles - irq_off.since > longest) {
    longest = cycles - irq_off.since;
    longest_at = irq_off.since;
    longest_pc = irq_off.pc;
  }
  char where[160] = "";
  if (longest) code_name(longest_pc, where, sizeof where);
  OUT("%s],\n  \"interrupts_off\": {\"longest_cycles\": %" PRIu64 ", \"longest_us\": %.3f, \"from\": \"%s\", "
      "\"at_cycle\": %" PRIu64 "}",
      tops ? "\n  " : "", longest, (double)longest * 1e6 / (double)engine.clock_hz, where, longest_at);
  OUT(",\n  \"usart_overruns\": [%u, %u, %u, %u],\n  \"stack\": {\"ram_end\": %u, \"bss_end\": %u, \"lowest_sp\": %u, \"worst_depth_bytes\": %u, "
      "\"free_ram_bytes\": %d}\n}\n",
      avr_usart_overruns(0), avr_usart_overruns(1), avr_usart_overruns(2), avr_usart_overruns(3),
      (unsigned)avr->ramend, engine.bss_end, engine.lowest_sp,
      (unsigned)(avr->ramend - engine.lowest_sp), (int)engine.lowest_sp - (int)engine.bss_end);
#undef OUT
  if (n >= sizeof text) n = sizeof text - 1;
  if (pwrite(report_fd, text, n, 0) != (ssize_t)n || ftruncate(report_fd, (off_t)n) != 0)
    fprintf(stderr, "sear-avr-engine: cannot write its report\n");
}
