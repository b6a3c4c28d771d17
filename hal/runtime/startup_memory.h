/* Memory that reads the same in every run, as a chip's does at every reset (startup_memory.c). */
#ifndef SEAR_HAL_RUNTIME_STARTUP_MEMORY_H
#define SEAR_HAL_RUNTIME_STARTUP_MEMORY_H

/* Paints the stack the lockstep hand-off just used, below the caller's frame: call it right
 * after the wait returns, from the function that called it. */
void mcu_paint_after_wait(void);

#endif
