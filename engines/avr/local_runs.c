/* Which instructions a local run (local_runs.h) may hold, by their encodings in the AVR
 * instruction set manual, each flash word's budget from them, and the register hooks that end a
 * run where one-by-one stepping would have looked. */
#include "local_runs.h"

#include <stdlib.h>

#include <sim_avr.h>
#include <sim_io.h>

#include "engine.h"

uint16_t avr_run_budget[AVR_PROFILE_WORDS];

/* Straight: goes on to the next instruction and changes the I flag only by a store to SREG
 * (hooked); its size in words, else 0 for the rest: skips, branches, jumps, calls, returns,
 * BSET/BCLR, which decode() sorts, and SLEEP, BREAK, WDR, SPM, DES, LPM and ELPM into R0 (0x95c8,
 * 0x95d8, rare and left alone), the XMEGA-only XCH and LA* and reserved encodings, which run
 * alone. */
static uint8_t straight_words(uint16_t op) {
  const uint8_t one = 1, two = 2;
  switch (op >> 12) {
  case 0x0: /* NOP, MOVW, MULS, MULSU/FMUL*, CPC, SBC, ADD */
    return (op & 0xff00) != 0x0000 || op == 0x0000 ? one : 0;
  case 0x1: /* CPSE skips; CP, SUB, ADC */
    return (op & 0xfc00) == 0x1000 ? 0 : one;
  case 0x2: case 0x3: case 0x4: case 0x5: case 0x6: case 0x7: /* AND EOR OR MOV, CPI SBCI SUBI ORI ANDI */
  case 0x8: case 0xa: /* LDD, STD (LD and ST through Y and Z) */
  case 0xb: /* IN, OUT */
  case 0xe: /* LDI */
    return one;
  case 0x9:
    switch ((op >> 8) & 0xf) {
    case 0x0: case 0x1: /* LDS, LD Z+/-Z, LPM Z/Z+, ELPM Z/Z+, LD Y+/-Y, LD X/X+/-X, POP */
      switch (op & 0xf) {
      case 0x0: return two;
      case 0x1: case 0x2: case 0x4: case 0x5: case 0x6: case 0x7:
      case 0x9: case 0xa: case 0xc: case 0xd: case 0xe: case 0xf: return one;
      default: return 0;
      }
    case 0x2: case 0x3: /* STS, ST Z+/-Z, ST Y+/-Y, ST X/X+/-X, PUSH */
      switch (op & 0xf) {
      case 0x0: return two;
      case 0x1: case 0x2: case 0x9: case 0xa: case 0xc: case 0xd: case 0xe: case 0xf: return one;
      default: return 0;
      }
    case 0x4: case 0x5: /* COM NEG SWAP INC ASR LSR ROR DEC */
      switch (op & 0xf) {
      case 0x0: case 0x1: case 0x2: case 0x3: case 0x5: case 0x6: case 0x7: case 0xa: return one;
      default: return 0;
      }
    case 0x6: case 0x7: /* ADIW, SBIW */
    case 0x8: case 0xa: /* CBI, SBI */
    case 0xc: case 0xd: case 0xe: case 0xf: /* MUL */
      return one;
    default: /* SBIC, SBIS */
      return 0;
    }
  case 0xf: /* BLD, BST; branches and SBRC/SBRS are not */
    return (op & 0xfc08) == 0xf800 ? one : 0;
  default: /* RJMP, RCALL */
    return 0;
  }
}

/* A store to SREG ends the run after its instruction, and so does one that takes the stack
 * pointer below its lowest yet: the loop then sees the I flag and the stack's low mark at the
 * cycle they changed (a PUSH or POP that stays above the mark changes neither). simavr calls a
 * hook on these registers instead of storing (sim_core.c's _avr_set_r; SREG's bits it splits out
 * before). SPL and SPH are stored one at a time; whichever comes second sees the whole new
 * pointer, and a half-stored one read low only ends a run early. */
static void sreg_stored(struct avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param) {
  (void)param;
  avr->data[addr] = v;
  avr->run_cycle_count = 0;
}

static void stack_pointer_stored(struct avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param) {
  (void)param;
  avr->data[addr] = v;
  /* From v, not from the byte just stored (which a 16-bit load would wait for). */
  const uint16_t sp = (uint16_t)(addr == R_SPL ? v | avr->data[R_SPH] << 8 : avr->data[R_SPL] | v << 8);
  if (sp < engine.lowest_sp) avr->run_cycle_count = 0;
}

/* What an instruction is to a run. */
enum role {
  ALONE,  /* the loop looks at it before it runs: a run stops short of it */
  LAST,   /* what it changes (the I flag, the function) is looked at after it: a run may end with it */
  INSIDE, /* goes on to its successors, all within its own function */
};

struct instruction {
  uint8_t role;
  uint8_t nexts;
  uint32_t next[2]; /* words */
};

/* As simavr's _avr_is_instruction_32_bits: how far a skip skips. */
static int two_words(uint16_t op) {
  const uint16_t o = op & 0xfc0f;
  return o == 0x9000 || o == 0x9200 || (o >= 0x940c && o <= 0x940f);
}

static int32_t signed_bits(uint32_t value, unsigned bits) {
  return (int32_t)(value << (32 - bits)) >> (32 - bits);
}

/* The instruction at word w (of `words` in the image), and where it may go on to. A jump to
 * itself runs alone (the loop's halt check is made per instruction), and so does one out of the
 * image (the loop's report names its pc); one with a successor outside its own symbol (`lo` to
 * `hi`) is LAST, so that a run's cycles all belong to the function it began in (the profile sums
 * them per function). */
static struct instruction decode(const uint8_t *flash, uint32_t w, uint32_t words, uint32_t lo, uint32_t hi) {
#define WORD(at) ((uint16_t)(flash[2 * (at)] | flash[2 * (at) + 1] << 8))
  const uint16_t op = WORD(w);
  struct instruction in = {ALONE, 0, {0, 0}};
  int64_t to[2];
  int n = 0;
  const uint8_t size = straight_words(op);
  if (size) {
    to[n++] = (int64_t)w + size;
  } else if ((op & 0xf800) == 0xf000) { /* BRBS, BRBC */
    to[n++] = (int64_t)w + 1;
    to[n++] = (int64_t)w + 1 + signed_bits((op >> 3) & 0x7f, 7);
  } else if ((op & 0xf000) == 0xc000) { /* RJMP */
    to[n++] = (int64_t)w + 1 + signed_bits(op & 0x0fff, 12);
  } else if ((op & 0xfe0e) == 0x940c) { /* JMP */
    if (w + 1 >= words) return in;
    to[n++] = (int64_t)((uint32_t)(((op >> 3) & 0x3e) | (op & 1)) << 16 | WORD(w + 1));
  } else if ((op & 0xfc00) == 0x1000 || (op & 0xfc08) == 0xfc00 || (op & 0xfd00) == 0x9900) {
    /* CPSE, SBRC/SBRS, SBIC/SBIS: the next instruction, or the one after it */
    if (w + 1 >= words) return in;
    to[n++] = (int64_t)w + 1;
    to[n++] = (int64_t)w + (two_words(WORD(w + 1)) ? 3 : 2);
  } else if ((op & 0xff0f) == 0x9408 && ((op >> 4) & 7) != 7) { /* BSET, BCLR but SEI and CLI */
    to[n++] = (int64_t)w + 1;
  } else {
    /* IJMP and EIJMP run alone: through Z to themselves they are a halt, which the loop must
     * see when they begin. The calls and returns move the stack pointer, so they cannot be one. */
    const int last = op == 0x9478 || op == 0x94f8 ||                         /* SEI, CLI */
                     (op & 0xfe0e) == 0x940e || (op & 0xf000) == 0xd000 ||    /* CALL, RCALL */
                     op == 0x9509 || op == 0x9519 || op == 0x9508 || op == 0x9518; /* (E)ICALL, RET, RETI */
    in.role = last ? LAST : ALONE;
    return in;
  }
#undef WORD
  /* A jump to itself, or into nowhere (the loop's report names this jump). */
  for (int i = 0; i < n; ++i)
    if (to[i] == (int64_t)w || to[i] < 0 || to[i] >= (int64_t)words) return in;
  for (int i = 0; i < n; ++i)
    if (to[i] < (int64_t)lo || to[i] >= (int64_t)hi) {
      in.role = LAST;
      return in;
    }
  in.role = INSIDE;
  for (int i = 0; i < n; ++i) in.next[in.nexts++] = (uint32_t)to[i];
  return in;
}

/* Each word's budget: the fewest instructions on any path from it to and with a LAST one, or up
 * to an ALONE one, a breadth-first search back from those over the INSIDE ones' successors. A word
 * no path leads from to either (a loop within a function that never leaves it) is bounded only by
 * the cycle timers, as single steps are. */
static int set_budgets(const uint8_t *flash, uint32_t words) {
  struct instruction *code = malloc((size_t)words * sizeof *code);
  uint32_t *first_from = calloc((size_t)words + 1, sizeof *first_from); /* predecessors, CSR */
  uint32_t *from = NULL, *queue = NULL;
  uint32_t *dist = NULL;
  int ok = 0;
  if (!code || !first_from) goto out;
  for (uint32_t w = 0; w < words; ++w) {
    uint32_t lo, hi;
    avr_profile_symbol_words(w, &lo, &hi);
    code[w] = decode(flash, w, words, lo, hi);
    for (int i = 0; i < code[w].nexts; ++i) first_from[code[w].next[i] + 1]++;
  }
  for (uint32_t w = 0; w < words; ++w) first_from[w + 1] += first_from[w];
  from = malloc(((size_t)first_from[words] + 1) * sizeof *from);
  queue = malloc((size_t)words * sizeof *queue);
  dist = malloc((size_t)words * sizeof *dist);
  if (!from || !queue || !dist) goto out;
  {
    uint32_t *fill = queue; /* borrowed as each word's fill position before the search */
    for (uint32_t w = 0; w < words; ++w) fill[w] = first_from[w];
    for (uint32_t w = 0; w < words; ++w)
      for (int i = 0; i < code[w].nexts; ++i) from[fill[code[w].next[i]]++] = w;
  }
  uint32_t head = 0, tail = 0;
  for (uint32_t w = 0; w < words; ++w) dist[w] = UINT32_MAX;
  for (int role = ALONE; role <= LAST; ++role) /* the queue in order of distance */
    for (uint32_t w = 0; w < words; ++w)
      if (code[w].role == role) {
        dist[w] = role == ALONE ? 0 : 1;
        queue[tail++] = w;
      }
  while (head < tail) {
    const uint32_t v = queue[head++];
    for (uint32_t i = first_from[v]; i < first_from[v + 1]; ++i) {
      const uint32_t u = from[i];
      if (dist[u] != UINT32_MAX) continue;
      dist[u] = dist[v] + 1;
      queue[tail++] = u;
    }
  }
  /* A run that would begin at a LAST one is that one instruction: it runs as a single step. */
  for (uint32_t w = 0; w < words; ++w)
    avr_run_budget[w] = code[w].role != INSIDE ? 0 : (uint16_t)(dist[w] < UINT16_MAX ? dist[w] : UINT16_MAX);
  ok = 1;
out:
  free(code);
  free(first_from);
  free(from);
  free(queue);
  free(dist);
  return ok;
}

int avr_local_runs_init(uint32_t code_end) {
  avr_t *avr = engine.avr;
  const char *single = getenv("SEAR_AVR_SINGLE_STEP");
  if (single && *single && *single != '0') return 0;
  static const avr_io_addr_t hooked[] = {R_SREG, R_SPL, R_SPH};
  for (unsigned i = 0; i < sizeof hooked / sizeof *hooked; ++i)
    if (avr->io[AVR_DATA_TO_IO(hooked[i])].w.c) return 0;
  if (code_end > avr->flashend + 1) code_end = avr->flashend + 1;
  const uint32_t words = code_end / 2;
  for (uint32_t pc = 0; pc + 1 < code_end; pc += 2) {
    const uint16_t op = (uint16_t)(avr->flash[pc] | avr->flash[pc + 1] << 8);
    if (op == 0x95e8 || op == 0x95f8) return 0; /* SPM, SPM Z+ */
  }
  if (words && !set_budgets(avr->flash, words)) engine_fatal("out of memory for the engine's local runs");
  avr_register_io_write(avr, R_SREG, sreg_stored, NULL);
  avr_register_io_write(avr, R_SPL, stack_pointer_stored, NULL);
  avr_register_io_write(avr, R_SPH, stack_pointer_stored, NULL);
  return 1;
}
