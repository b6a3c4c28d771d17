/* A firmware in the states a run must be able to end from, chosen by LIFE_HOW (set per build by
 * tests/CMakeLists.txt): 1 forks a child that outlives nothing, then spins without HAL calls;
 * 2 sleeps in a host call; 3 stops itself with SIGSTOP; 4 prints a line every millisecond for
 * ever, for runs whose standard output closes early. Each first reports its pid (and the
 * child's) on the console and says "ready". */
#define _POSIX_C_SOURCE 200809L /* fork(), pause() */
#include <hal/hal.h>
#include <signal.h>
#include <stdio.h>
#include <unistd.h>

volatile unsigned long spins;

static void say(const char *text) {
  uart_print(0, text);
  uart_flush(0); /* on the wire, and so in the console log, before the state below begins */
  delay_ms(2);   /* and past the quantum's end, so that the simulator has written it */
}

int main(void) {
  char line[64];
  hal_init();
  uart_begin(0, 115200);
#if LIFE_HOW == 1
  const pid_t child = fork();
  if (child == 0) {
    for (;;) pause();
  }
  snprintf(line, sizeof line, "pid %d child %d\n", (int)getpid(), (int)child);
#else
  snprintf(line, sizeof line, "pid %d\n", (int)getpid());
#endif
  say(line);
  say("ready\n");
#if LIFE_HOW == 1
  for (;;) spins++;
#elif LIFE_HOW == 2
  for (;;) sleep(1000);
#elif LIFE_HOW == 3
  raise(SIGSTOP);
  for (;;) spins++;
#else
  for (unsigned long n = 0;; ++n) {
    snprintf(line, sizeof line, "line %lu\n", n);
    uart_print(0, line);
    delay_ms(1);
  }
#endif
}
