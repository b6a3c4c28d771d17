/* A physics failure made on purpose, for the tests, preloaded into `sear` (LD_PRELOAD): after ODE's
 * step number SEAR_TEST_BREAK_STEP, the first body the simulator created is left with a NaN
 * velocity, as a solver that blew up would leave it. No valid project can make ODE fail (the loader
 * refuses the values that would), and the simulator carries no hook for it; this lets a test follow
 * a run's whole path through a physics failure. ODE is reached through dlsym, so that the shell
 * the test starts `sear` from loads this library harmlessly too. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct dxWorld *dWorldID;
typedef struct dxBody *dBodyID;
typedef double dReal; /* Debian's libode is built in double precision */

/* dlsym's object pointer into a function pointer, as POSIX allows and ISO C does not say. */
static void look_up(void *function_pointer, size_t size, const char *name) {
  void *symbol = dlsym(RTLD_NEXT, name);
  memcpy(function_pointer, &symbol, size);
}

static dBodyID first_body;

dBodyID dBodyCreate(dWorldID world) {
  static dBodyID (*real)(dWorldID);
  if (!real) look_up(&real, sizeof real, "dBodyCreate");
  dBodyID body = real(world);
  if (!first_body) first_body = body;
  return body;
}

/* After the real step (`name`, either of ODE's solvers), the NaN at the step asked for. */
static int broken_step(int (**real)(dWorldID, dReal), const char *name, dWorldID world, dReal stepsize) {
  static void (*set_velocity)(dBodyID, dReal, dReal, dReal);
  static long steps, break_at = -1;
  if (!set_velocity) {
    look_up(&set_velocity, sizeof set_velocity, "dBodySetLinearVel");
    const char *at = getenv("SEAR_TEST_BREAK_STEP");
    break_at = at ? atol(at) : -1;
  }
  if (!*real) look_up(real, sizeof *real, name);
  const int result = (*real)(world, stepsize);
  if (++steps == break_at && first_body) set_velocity(first_body, NAN, 0, 0);
  return result;
}

int dWorldStep(dWorldID world, dReal stepsize) {
  static int (*real)(dWorldID, dReal);
  return broken_step(&real, "dWorldStep", world, stepsize);
}

int dWorldQuickStep(dWorldID world, dReal stepsize) {
  static int (*real)(dWorldID, dReal);
  return broken_step(&real, "dWorldQuickStep", world, stepsize);
}
