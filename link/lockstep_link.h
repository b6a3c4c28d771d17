/* The shared memory between the simulator and one MCU's firmware process: the wiring the
 * firmware's HAL needs, the lockstep hand-off, the sensor samples for the coming quantum, and the
 * time-stamped events the firmware produced. Plain C so that both sides include the one layout. */
#ifndef SEAR_LOCKSTEP_LINK_H
#define SEAR_LOCKSTEP_LINK_H

#include <stdint.h>

#define SEAR_LINK_MAGIC 0x52414553u /* "SEAR" little-endian */
#define SEAR_LINK_VERSION 8u
/* Guards at both ends of the firmware's writable part: a stray write that runs over them is seen
 * at the next turn even when every value it hit still looks plausible. */
#define SEAR_LINK_GUARD 0x5EA75EA75EA75EA7ull
/* The simulator passes the page to the firmware as an inherited file descriptor named here. */
#define SEAR_LINK_FD_ENV "SEAR_LINK_FD"
/* ... and names itself, so that a firmware outliving it can tell. */
#define SEAR_SIM_PID_ENV "SEAR_SIM_PID"
/* An MCU whose EEPROM the project keeps (<eeprom persist="true">) inherits its file, opened for
 * reading and writing, as the descriptor named here: its first 4096 bytes are the cells (a shorter
 * file is erased past its end), and each write goes to it at once. Without it the EEPROM starts
 * erased. A descriptor rather than a path keeps the firmware's environment the same size wherever
 * the project lies. */
#define SEAR_EEPROM_FD_ENV "SEAR_EEPROM_FD"

#define SEAR_LINK_PINS 70
#define SEAR_LINK_ADC_CHANNELS 16
#define SEAR_LINK_UARTS 4
#define SEAR_LINK_MAX_INPUTS 32
#define SEAR_LINK_MAX_SAMPLES 256
#define SEAR_LINK_MAX_RX 8192 /* 10 ms (the longest step) at 2 Mbaud on all four ports */
#define SEAR_LINK_MAX_EVENTS 2048
/* CAN records towards the firmware per quantum: a 10 ms step at 1 Mbit/s carries at most 212
 * frames (47 bits each, the shortest), each a reception or a transmission's outcome. */
#define SEAR_LINK_MAX_CAN 512

/* Every HAL entry point, so a report can name the last one a firmware called. */
#define SEAR_HAL_CALLS(X)                                                                            \
  X(none) X(hal_init) X(millis) X(micros) X(delay_ms) X(delay_us) X(pin_mode) X(digital_read)        \
  X(digital_write) X(digital_toggle) X(adc_reference) X(adc_resolution) X(adc_read) X(pwm_write)     \
  X(servo_write_us) X(uart_begin) X(uart_available) X(uart_read) X(uart_write) X(uart_print)         \
  X(uart_flush) X(spi_begin) X(spi_transfer) X(i2c_begin) X(i2c_write) X(i2c_read) X(i2c_write_reg) \
  X(i2c_read_regs) X(irq_attach_pin) X(irq_detach_pin) X(irq_timer_start) X(irq_timer_stop)         \
  X(irq_attach_uart_rx) X(irq_disable) X(irq_enable) X(can_begin) X(can_send) X(can_tx_pending)         \
  X(can_available) X(can_receive) X(can_set_mask) X(can_set_filter) X(can_get_counters) X(can_attach_rx) \
  X(i2c_write_read) X(i2c_write_nostop) X(uart_tx_space) X(pulse_in) X(eeprom_read) X(eeprom_write) \
  X(hal_refuse) X(soft_uart_begin) X(soft_uart_end) X(soft_uart_listen) X(soft_uart_is_listening)      \
  X(soft_uart_available) X(soft_uart_read) X(soft_uart_peek) X(soft_uart_write) X(soft_uart_overflow)    \
  X(soft_uart_stop_listening)

#define SEAR_CALL_ENUM(name) SEAR_CALL_##name,
enum sear_call { SEAR_HAL_CALLS(SEAR_CALL_ENUM) SEAR_CALL_COUNT };
#undef SEAR_CALL_ENUM

/* Whose turn it is; the word the hand-off spins and sleeps on. */
enum sear_turn { SEAR_TURN_SIM = 0, SEAR_TURN_FIRMWARE = 1 };

/* Why the firmware handed the turn back. */
enum sear_request {
  SEAR_REQUEST_QUANTUM_DONE = 0, /* its clock reached quantum_end_ns */
  SEAR_REQUEST_DRAIN = 1,        /* its event queue is full: empty it, same quantum */
  SEAR_REQUEST_EXIT = 2,         /* main() returned or exit() was called */
  SEAR_REQUEST_FATAL = 3         /* the HAL refused a call; `fatal` says why */
};

/* Whether the MCU halted for good: its firmware is in an endless empty loop (`while (true);`,
 * `for (;;);`; on the chip `rjmp .-2`) that nothing but an interrupt can preempt. It stays in the
 * run: its interrupts still run (while they are enabled), its queued bytes still leave. */
enum sear_halt {
  SEAR_HALT_NONE = 0,
  SEAR_HALT_EMPTY_LOOP = 1,        /* interrupts on: timers, pins and ports still interrupt it */
  SEAR_HALT_EMPTY_LOOP_IRQ_OFF = 2 /* interrupts off (or inside a handler): nothing more runs */
};

/* What a wired input is: a device whose model runs in the firmware's process (DESIGN.md, "Where
 * device models run"). The simulator sends it physical truth as samples; the model turns them into
 * volts, levels, edges or registers. Each kind says what its pins[], param[] and sample values hold. */
enum sear_input_kind {
  SEAR_INPUT_GP2D12 = 1, /* pins[0] ADC channel; param[0] noise sd (V); value[0] distance (m, inf: none) */
  SEAR_INPUT_GP2D15 = 2, /* pins[0] output pin; param[0] switch distance, [1] hysteresis (m); value[0] distance */
  SEAR_INPUT_SWITCH = 3, /* pins[0] pin; value[0] 1 closed (to ground) or 0 open */
  /* HC-SR04: pins[0] TRIG (the firmware drives it), pins[1] ECHO; value[0] distance (m, inf: none),
   * the latest measured, held until the next sample */
  SEAR_INPUT_HCSR04 = 4,
  /* MaxBotix LV-EZ analog and pulse-width outputs: pins[0] ADC channel, pins[1] PW pin (either
   * SEAR_LINK_NO_PIN); one sample per reading at its cycle's start, value[0] the reading in inches */
  SEAR_INPUT_MAXBOTIX = 5,
  /* Quadrature encoder: pins[0] A, pins[1] B; param[0] cycles per revolution; one sample per
   * quantum: value[0] shaft angle (rad, never wrapped), value[1] its rate (rad/s) */
  SEAR_INPUT_ENCODER = 6,
  /* MPU-6000 on SPI / MPU-6050 on I2C: pins[0] chip select (6000) or I2C address (6050), pins[1]
   * data-ready INT pin or SEAR_LINK_NO_PIN; param[0] gyro noise density (rad/s/sqrt(Hz)),
   * param[1] gyro turn-on bias sd (rad/s), param[2] accel noise density (m/s^2/sqrt(Hz)), each
   * < 0 for the datasheet's, param[3] the self-test response's error against its trim (a
   * fraction, 0 for a healthy part); one sample per quantum: value[0..2] specific force (m/s^2),
   * value[3..5] angular rate (rad/s), in the sensor's axes */
  SEAR_INPUT_MPU6000 = 7,
  SEAR_INPUT_MPU6050 = 8,
  /* HMC5883L / QMC5883L on I2C: pins[0] I2C address, pins[1] the HMC's DRDY pin or
   * SEAR_LINK_NO_PIN; one sample per quantum: value[0..2] the field in the sensor's axes (T) */
  SEAR_INPUT_HMC5883L = 9,
  SEAR_INPUT_QMC5883L = 10,
  /* A UART device of the simulator's process wired to two plain pins (a soft UART): pins[0] the
   * firmware's RX pin, which the device's TX drives; pins[1] the firmware's TX pin, which the
   * simulator decodes from its PIN events; param[0] 1 when the device's TX has RS-232 polarity at
   * logic levels (idle low, bits inverted). One sample per byte the device sends: time = the
   * leading edge of its start bit, value[0] the byte, value[1] the baud; the model plays the
   * frame out as edges on pins[0]. */
  SEAR_INPUT_UART_PINS = 11,
  SEAR_INPUT_KIND_END
};

#define SEAR_LINK_INPUT_PINS 4
#define SEAR_LINK_INPUT_PARAMS 8
#define SEAR_LINK_SAMPLE_VALUES 6
#define SEAR_LINK_NO_PIN 0xFFu
/* How many values a reading of each kind holds, by enum sear_input_kind (0 for none). */
#define SEAR_LINK_READING_VALUES_BY_KIND 0, 1, 1, 1, 2, 2, 2, 6, 6, 3, 3, 0

struct sear_link_input {
  uint32_t kind;                         /* enum sear_input_kind */
  uint32_t pins[SEAR_LINK_INPUT_PINS];   /* pins, ADC channels, chip selects or addresses; SEAR_LINK_NO_PIN unused */
  uint64_t seed;                         /* for the device's noise */
  double param[SEAR_LINK_INPUT_PARAMS];  /* the device's figures, per kind */
};

/* What an input's model last gave the firmware (volts on its ADC channel, the level it drives,
 * the echo it timed, the count its edges make, its data registers decoded), from `time_ns` on:
 *   GP2D12   value[0] output (V)                GP2D15  value[0] output level (0/1)
 *   SWITCH   value[0] 1 closed, 0 open          HCSR04  value[0] last echo's width (s), [1] its distance (m)
 *   MAXBOTIX value[0] analog output (V), [1] the reading (in)
 *   ENCODER  value[0] count (4 per cycle, signed), [1] the angle it means (rad)
 *   MPU6000/6050 value[0..2] accel (m/s^2), [3..5] gyro (rad/s), at the configured full scales
 *   HMC5883L/QMC5883L value[0..2] field (T) at the configured gain
 * The firmware's process writes the values and time, then bumps `count`, whenever they change. */
struct sear_link_reading {
  int64_t time_ns;
  uint32_t count;
  uint32_t reserved;
  double value[SEAR_LINK_SAMPLE_VALUES];
};

struct sear_link_sample {
  int64_t time_ns;
  uint64_t index; /* the device's measurement number, for its noise */
  uint32_t input; /* into inputs[] */
  uint32_t reserved;
  double value[SEAR_LINK_SAMPLE_VALUES];
};

/* What the bus did for this MCU's CAN controller, at time_ns: a frame it received (before its
 * acceptance filters, which run in the firmware's process), or the outcome of one of its own. */
enum sear_can_record {
  SEAR_CAN_RECEIVED = 1, /* time = end of the frame */
  SEAR_CAN_SENT = 2,     /* its oldest waiting frame went out and was acknowledged; time = its end */
  SEAR_CAN_NO_ACK = 3    /* its oldest waiting frame went unacknowledged; it is sent again */
};
/* The bit rates a CAN controller of hal/can.h makes (an MCP2515 at 16 MHz makes each exactly). */
#define SEAR_CAN_BITRATES 10000u, 20000u, 50000u, 100000u, 125000u, 250000u, 500000u, 1000000u
#define SEAR_CAN_EXTENDED 1u
#define SEAR_CAN_REMOTE 2u

struct sear_link_can {
  int64_t time_ns;
  uint32_t id;
  uint8_t record; /* enum sear_can_record */
  uint8_t flags;  /* SEAR_CAN_EXTENDED, SEAR_CAN_REMOTE */
  uint8_t dlc;
  uint8_t tec;    /* the controller's error counters after this record */
  uint8_t rec;
  uint8_t reserved[3];
  uint8_t data[8];
};

struct sear_link_rx {
  int64_t time_ns; /* when the stop bit ends */
  uint8_t port;
  uint8_t byte;
  uint8_t reserved[6];
};

enum sear_event_kind {
  SEAR_EVENT_PIN = 1,        /* index = pin, value = level driven (0/1) */
  SEAR_EVENT_PIN_MODE = 2,   /* index = pin, value = INPUT/OUTPUT/INPUT_PULLUP */
  SEAR_EVENT_PWM = 3,        /* index = pin, value = duty 0..255 */
  SEAR_EVENT_SERVO = 4,      /* index = pin, value = pulse in microseconds, 0 = off */
  SEAR_EVENT_UART_BEGIN = 5, /* index = port, value = baud */
  SEAR_EVENT_UART_TX = 6,    /* index = port, value = byte; time = end of its stop bit */
  SEAR_EVENT_UART_RX = 7,    /* index = port, value = byte; time = end of its stop bit */
  SEAR_EVENT_CAN_BEGIN = 8,  /* index 0, value = bit rate */
  /* A frame queued for sending: index = dlc | SEAR_CAN_* flags << 4, value = identifier; the two
   * CAN_DATA events that follow at once carry its data bytes 0-3 (index 0) and 4-7 (index 1),
   * little-endian. */
  SEAR_EVENT_CAN_TX = 9,
  SEAR_EVENT_CAN_DATA = 10,
  /* A device in the firmware's process drives a pin (an echo, an encoder channel, a data-ready
   * line, a switch): index = pin, value = level 0/1, or 2 when it lets go; time = the device's
   * own edge. For the waveforms: the firmware reads these levels itself. */
  SEAR_EVENT_PIN_DRIVEN = 11
};

struct sear_event {
  int64_t time_ns;
  uint32_t value;
  uint8_t kind;
  uint8_t index;
  uint8_t reserved[2];
};

/* See sear_link.usage. */
struct sear_link_usage {
  uint32_t usage_kept;
  uint32_t adc_read;         /* bit n: adc_read(n) was called */
  uint32_t inputs_addressed; /* bit i: inputs[i] was selected for an SPI transfer or addressed on I2C */
  uint32_t reserved;
  uint8_t pin_read[SEAR_LINK_PINS]; /* 1: read by digital_read or pulse_in, or given an interrupt */
  /* 1 + the level of the first digital_write/digital_toggle on a pin that had never been an
   * OUTPUT (on the chip that only switches its pull-up), at input_write_ns; 0: none */
  uint8_t input_write[SEAR_LINK_PINS];
  int64_t input_write_ns[SEAR_LINK_PINS];
};

struct sear_link {
  uint32_t magic;
  uint32_t version;
  uint64_t guard_front;

  /* Set once by the simulator before the firmware starts. */
  int64_t hal_call_cost_ns;
  double avcc_v;
  double aref_v;
  uint32_t input_count;
  uint32_t uart_loopback_mask; /* bit n: port n's TX is wired to its own RX */
  struct sear_link_input inputs[SEAR_LINK_MAX_INPUTS];

  /* The hand-off. Accessed only with __atomic builtins. */
  uint32_t turn;
  uint32_t sim_waiting;
  uint32_t firmware_waiting;
  uint32_t request; /* enum sear_request, written by the firmware before it hands back */

  /* Written by the simulator before it hands the turn to the firmware. */
  int64_t quantum_end_ns;
  uint32_t sample_count;
  uint32_t rx_count;
  uint32_t can_count;
  uint32_t reserved_count;
  struct sear_link_sample samples[SEAR_LINK_MAX_SAMPLES]; /* in time order */
  struct sear_link_rx rx[SEAR_LINK_MAX_RX];               /* in time order */
  struct sear_link_can can[SEAR_LINK_MAX_CAN];            /* in time order */

  /* Written by the firmware on every HAL call, read by the simulator for reports. */
  int64_t clock_ns;
  uint64_t calls;
  uint32_t last_call; /* enum sear_call */
  int32_t exit_code;
  char fatal[192];
  /* An engine that counts the chip's cycles (the AVR engine) writes, at the end of each quantum,
   * the cycles run so far and how many of them were busy (not asleep); the native engine cannot
   * tell and leaves both 0. */
  uint64_t chip_cycles;
  uint64_t chip_busy_cycles;
  /* Written once, when the MCU halts (enum sear_halt), with its clock at that moment. */
  int64_t halted_ns;
  uint32_t halt;
  uint32_t reserved_halt;

  /* Written by the firmware during its quantum, emptied by the simulator at its turn. */
  uint32_t event_count;
  uint32_t reserved;
  struct sear_event events[SEAR_LINK_MAX_EVENTS];

  /* Written by the firmware's process whenever a model's output changes; read by the simulator
   * after each turn. Per input, as inputs[]. */
  struct sear_link_reading readings[SEAR_LINK_MAX_INPUTS];

  /* What the firmware used that leaves no event, for the run's wiring report. Written by the
   * native runtime, which sets `usage_kept`; an engine that leaves it 0 reports none of it. The
   * simulator reads only flags and times out of it, so nonsense here costs a wrong note, no more. */
  struct sear_link_usage usage;
  uint64_t guard_back;
};

#endif
