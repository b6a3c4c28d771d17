/* avr-libc's number formatting, which Debian's WString calls and glibc lacks: itoa and its
 * kin, and dtostrf ("%*.*f"). */
#include <stdio.h>
#include <stdlib.h>

char *itoa(int value, char *s, int radix);
char *ltoa(long value, char *s, int radix);
char *utoa(unsigned int value, char *s, int radix);
char *ultoa(unsigned long value, char *s, int radix);
char *dtostrf(double val, signed char width, unsigned char prec, char *s);

char *ultoa(unsigned long value, char *s, int radix) {
  char digits[8 * sizeof value + 1];
  int n = 0;
  if (radix < 2 || radix > 36) radix = 10;
  do {
    const unsigned long d = value % (unsigned long)radix;
    digits[n++] = (char)(d < 10 ? '0' + d : 'a' + d - 10);
    value /= (unsigned long)radix;
  } while (value);
  for (int i = 0; i < n; ++i) s[i] = digits[n - 1 - i];
  s[n] = '\0';
  return s;
}

/* As avr-libc: a minus sign only in radix 10; other radices show the two's complement. */
char *ltoa(long value, char *s, int radix) {
  if (radix == 10 && value < 0) {
    s[0] = '-';
    ultoa(0ul - (unsigned long)value, s + 1, radix);
    return s;
  }
  return ultoa((unsigned long)value, s, radix);
}

char *utoa(unsigned int value, char *s, int radix) { return ultoa(value, s, radix); }

char *itoa(int value, char *s, int radix) {
  if (radix == 10) return ltoa(value, s, radix);
  return ultoa((unsigned int)value, s, radix);
}

char *dtostrf(double val, signed char width, unsigned char prec, char *s) {
  sprintf(s, "%*.*f", width, prec, val);
  return s;
}
