/* The 10-bit ADC on A0..A15: reference selection, 8- or 10-bit results, one conversion at a
 * time by polling (13 ADC clocks at 125 kHz, 104 us). */
#include <hal/adc.h>

#include <avr/io.h>

/* ADMUX's REFS1:0 for the next conversion: AVCC is the reset-time choice of the HAL. */
static uint8_t reference_bits = _BV(REFS0);
static uint8_t left_adjust; /* ADLAR when adc_resolution(8) asked for the top 8 bits only */

void adc_reference(uint8_t reference)
{
    switch (reference) {
    case ADC_REF_AVCC: reference_bits = _BV(REFS0); break;
    case ADC_REF_EXTERNAL: reference_bits = 0; break;
    case ADC_REF_1V1: reference_bits = _BV(REFS1); break; /* on the 2560 */
    case ADC_REF_2V56: reference_bits = _BV(REFS1) | _BV(REFS0); break;
    default: break;
    }
}

void adc_resolution(uint8_t bits)
{
    if (bits == 8)
        left_adjust = _BV(ADLAR);
    else if (bits == 10)
        left_adjust = 0;
}

static void convert(void)
{
    ADCSRA |= _BV(ADSC);
    while (ADCSRA & _BV(ADSC)) {
    }
}

uint16_t adc_read(uint8_t channel)
{
    if (channel >= HAL_ADC_CHANNELS)
        return 0;
    /* Channels 8..15 (ADC8..ADC15 on port K) are single-ended inputs with MUX5 set. */
    if (channel & 8)
        ADCSRB |= _BV(MUX5);
    else
        ADCSRB &= (uint8_t)~_BV(MUX5);
    uint8_t changed_reference = (uint8_t)((ADMUX ^ reference_bits) & (_BV(REFS1) | _BV(REFS0)));
    ADMUX = (uint8_t)(reference_bits | left_adjust | (channel & 7u));
    /* The datasheet advises discarding the first result after the reference changes (the
     * bandgap and the AREF capacitor need that long to settle). */
    if (changed_reference)
        convert();
    convert();
    if (left_adjust)
        return ADCH;
    uint8_t low = ADCL; /* ADCL first: reading it locks ADCH until ADCH has been read */
    uint8_t high = ADCH;
    return (uint16_t)((uint16_t)high << 8 | low);
}
