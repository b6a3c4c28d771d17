/* The analog-to-digital converter: 16 channels (pins A0..A15), 10 bits by default
 * (0..1023 = 0 V..Vref), against AVCC (5 V), the AREF pin (3.3 V on SEAR's reference board),
 * the internal 1.1 V bandgap or the internal 2.56 V reference. reading = Vin * 1024 / Vref, clamped to the top code. */
#ifndef SEAR_HAL_ADC_H
#define SEAR_HAL_ADC_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HAL_ADC_CHANNELS 16

#define ADC_REF_AVCC 0     /* 5 V supply (the default) */
#define ADC_REF_EXTERNAL 1 /* the AREF pin, wired to 3.3 V */
#define ADC_REF_1V1 2      /* internal bandgap, 1.1 V */
#define ADC_REF_2V56 3     /* internal 2.56 V (REFS1:0 = 11 on the ATmega2560) */

void adc_reference(uint8_t reference);
void adc_resolution(uint8_t bits);  /* 10 (default) or 8 */
uint16_t adc_read(uint8_t channel); /* one conversion: 13 ADC clocks at 125 kHz, 104 us */

#ifdef __cplusplus
}
#endif
#endif
