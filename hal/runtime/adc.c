/* The ADC: the voltage a device puts on a channel, quantised against the selected reference. */
#include <hal/adc.h>

#include "mcu.h"

/* 13 ADC clocks at 16 MHz / 128 (datasheet section 26.4): the read blocks this long. */
#define CONVERSION_NS 104000

void adc_reference(uint8_t reference) {
  mcu_enter(SEAR_CALL_adc_reference);
  if (reference > ADC_REF_2V56)
    mcu_fatal("adc_reference(%u): use ADC_REF_AVCC, ADC_REF_EXTERNAL, ADC_REF_1V1 or ADC_REF_2V56", reference);
  sear_mcu.adc_reference = reference;
}

void adc_resolution(uint8_t bits) {
  mcu_enter(SEAR_CALL_adc_resolution);
  if (bits != 8 && bits != 10) mcu_fatal("adc_resolution(%u): the ATmega2560's ADC gives 10 or 8 bits", bits);
  sear_mcu.adc_bits = bits;
}

uint16_t adc_read(uint8_t channel) {
  const int64_t now = mcu_enter(SEAR_CALL_adc_read);
  if (channel >= HAL_ADC_CHANNELS) mcu_fatal("adc_read(%u): the ATmega2560 has channels 0..15", channel);
  sear_mcu.link->usage.adc_read |= 1u << channel;
  const struct sear_link *link = sear_mcu.link;
  const double vref = sear_mcu.adc_reference == ADC_REF_AVCC       ? link->avcc_v
                      : sear_mcu.adc_reference == ADC_REF_EXTERNAL ? link->aref_v
                      : sear_mcu.adc_reference == ADC_REF_2V56     ? 2.56
                                                                   : 1.1;
  /* The sample-and-hold takes the input at the start of the conversion. */
  const double vin = sear_mcu.analog_v[channel];
  double code = vin * 1024.0 / vref;
  if (code < 0) code = 0;
  if (code > 1023) code = 1023;
  mcu_advance_to(now + CONVERSION_NS);
  const uint16_t reading = (uint16_t)code;
  return sear_mcu.adc_bits == 8 ? (uint16_t)(reading >> 2) : reading;
}
