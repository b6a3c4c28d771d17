/* The TWI master on SDA 20 (PD1) and SCL 21 (PD0), every step checked against the datasheet's
 * status codes and bounded in time: a missing device or a stuck bus gives I2C_NACK, not a hang. */
#include <hal/i2c.h>

#include <avr/io.h>
#include <util/delay.h>
#include <util/twi.h>

/* A step that takes longer than this (SMBus gives up after 25..35 ms of clock stretching) means
 * the bus is stuck; 1 us per poll. */
#define STEP_TIMEOUT_US 25000u

static int8_t wait_for_twint(void)
{
    for (uint16_t waited = 0; waited < STEP_TIMEOUT_US; waited++) {
        if (TWCR & _BV(TWINT))
            return I2C_OK;
        _delay_us(1);
    }
    return I2C_NACK;
}

/* After a timeout, a bus error or lost arbitration the TWI may hold the bus: switching it off
 * and on releases SDA and SCL (datasheet: TWEN low ends any transmission). */
static void reset_bus(void)
{
    TWCR = 0;
    TWCR = _BV(TWEN);
}

static void stop(void)
{
    if (TW_STATUS == TW_MT_ARB_LOST) {
        reset_bus(); /* another master owns the bus: ours is not to stop */
        return;
    }
    TWCR = _BV(TWINT) | _BV(TWSTO) | _BV(TWEN);
    for (uint16_t waited = 0; TWCR & _BV(TWSTO); waited++) {
        if (waited >= STEP_TIMEOUT_US) {
            reset_bus();
            return;
        }
        _delay_us(1);
    }
}

/* Runs one bus step (TWCR = twcr) and returns I2C_OK when TWSR shows the expected status. */
static int8_t step(uint8_t twcr, uint8_t expected)
{
    TWCR = twcr;
    if (wait_for_twint() != I2C_OK) {
        reset_bus();
        return I2C_NACK;
    }
    return TW_STATUS == expected ? I2C_OK : I2C_NACK;
}

/* START (or repeated START) and SLA+R/W; on any failure the bus is released. */
static int8_t begin_transfer(uint8_t address, uint8_t read)
{
    if (!(TWCR & _BV(TWEN)))
        return I2C_NACK; /* i2c_begin not called */
    TWCR = _BV(TWINT) | _BV(TWSTA) | _BV(TWEN);
    if (wait_for_twint() != I2C_OK) {
        reset_bus();
        return I2C_NACK;
    }
    if (TW_STATUS != TW_START && TW_STATUS != TW_REP_START) {
        reset_bus(); /* bus error or lost arbitration: nothing of ours to stop */
        return I2C_NACK;
    }
    TWDR = (uint8_t)((address << 1) | (read ? TW_READ : TW_WRITE));
    if (step(_BV(TWINT) | _BV(TWEN), read ? TW_MR_SLA_ACK : TW_MT_SLA_ACK) != I2C_OK) {
        stop();
        return I2C_NACK;
    }
    return I2C_OK;
}

/* A data byte the slave did not acknowledge (TW_MT_DATA_NACK) is told apart from a stuck bus. */
static int8_t send_bytes(const uint8_t *data, uint8_t length)
{
    for (uint8_t i = 0; i < length; i++) {
        TWDR = data[i];
        if (step(_BV(TWINT) | _BV(TWEN), TW_MT_DATA_ACK) != I2C_OK) {
            int8_t refused = TW_STATUS == TW_MT_DATA_NACK ? I2C_NACK_DATA : I2C_NACK;
            stop();
            return refused;
        }
    }
    return I2C_OK;
}

/* ACK every byte but the last, whose NACK tells the slave to let go of SDA before STOP. */
static int8_t receive_bytes(uint8_t *data, uint8_t length)
{
    for (uint8_t i = 0; i < length; i++) {
        uint8_t last = (uint8_t)(i + 1u == length);
        if (step(last ? (_BV(TWINT) | _BV(TWEN)) : (_BV(TWINT) | _BV(TWEA) | _BV(TWEN)),
                 last ? TW_MR_DATA_NACK : TW_MR_DATA_ACK) != I2C_OK) {
            stop();
            return I2C_NACK;
        }
        data[i] = TWDR;
    }
    return I2C_OK;
}

void i2c_begin(uint32_t clock_hz)
{
    if (clock_hz == 0)
        return;
    /* SCL = F_CPU / (16 + 2 * TWBR * 4^TWPS): the smallest prescaler whose TWBR fits in a
     * byte, rounding up so the clock never exceeds what was asked (100 kHz: TWBR 72,
     * 400 kHz: TWBR 12). */
    uint32_t cycles = (F_CPU + clock_hz - 1u) / clock_hz;
    uint32_t twbr = cycles > 16u ? (cycles - 16u + 1u) / 2u : 0u;
    uint8_t prescaler = 0;
    while (twbr > 255u && prescaler < 3) {
        prescaler++;
        twbr = (twbr + 3u) / 4u;
    }
    if (twbr > 255u)
        twbr = 255u;
    /* The board has its own pull-ups; the internal ones (as Wire enables) only help short of
     * them. */
    PORTD |= _BV(PD0) | _BV(PD1);
    TWSR = prescaler; /* TWPS1:0 are TWSR's two low bits */
    TWBR = (uint8_t)twbr;
    TWCR = _BV(TWEN);
}

int8_t i2c_write(uint8_t address, const uint8_t *data, uint8_t length)
{
    int8_t result = i2c_write_nostop(address, data, length);
    if (result == I2C_OK)
        stop();
    return result;
}

/* No STOP: the next begin_transfer's START is a repeated start (TW_REP_START). */
int8_t i2c_write_nostop(uint8_t address, const uint8_t *data, uint8_t length)
{
    if (begin_transfer(address, 0) != I2C_OK)
        return I2C_NACK;
    return send_bytes(data, length);
}

int8_t i2c_write_read(uint8_t address, const uint8_t *out, uint8_t out_length, uint8_t *in, uint8_t in_length)
{
    uint8_t discard;
    int8_t result = i2c_write_nostop(address, out, out_length);
    if (result != I2C_OK)
        return result;
    if (begin_transfer(address, 1) != I2C_OK)
        return I2C_NACK;
    if (receive_bytes(in_length ? in : &discard, in_length ? in_length : 1) != I2C_OK)
        return I2C_NACK;
    stop();
    return I2C_OK;
}

int8_t i2c_read(uint8_t address, uint8_t *data, uint8_t length)
{
    uint8_t discard;
    if (begin_transfer(address, 1) != I2C_OK)
        return I2C_NACK;
    /* A master receiver must clock at least one byte before STOP (the slave may be driving
     * SDA), so a zero-length read takes one and throws it away. */
    if (receive_bytes(length ? data : &discard, length ? length : 1) != I2C_OK)
        return I2C_NACK;
    stop();
    return I2C_OK;
}

int8_t i2c_write_reg(uint8_t address, uint8_t reg, uint8_t value)
{
    uint8_t bytes[2] = {reg, value};
    return i2c_write(address, bytes, 2);
}

int8_t i2c_read_regs(uint8_t address, uint8_t first_reg, uint8_t *data, uint8_t length)
{
    uint8_t discard;
    if (begin_transfer(address, 0) != I2C_OK)
        return I2C_NACK;
    if (send_bytes(&first_reg, 1) != I2C_OK)
        return I2C_NACK;
    /* Repeated START: the register pointer must not be lost to another master in between. */
    if (begin_transfer(address, 1) != I2C_OK)
        return I2C_NACK;
    if (receive_bytes(length ? data : &discard, length ? length : 1) != I2C_OK)
        return I2C_NACK;
    stop();
    return I2C_OK;
}
