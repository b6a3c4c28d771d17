// A GPS on Serial1, read the way TinyGPS++ reads one: characters in as they come, each NMEA
// sentence's checksum verified, $GPGGA's fields taken apart; degrees kept as whole millionths in a
// long, so the sketch gives the same numbers on the Mega (32-bit long, 32-bit double) as here.
// Prints a line per valid fix: "fix <lat> <lon> sats <n> alt <m>", and "no fix" until there is one.
const long BAUD = 9600;  // the NEO-6M's at power-up

char sentence[83];  // NMEA 0183: at most 82 characters with $ and CR LF
int length = 0;
unsigned long good = 0, bad = 0;

int hexValue(char c) { return c >= '0' && c <= '9' ? c - '0' : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1; }

// The sentence's XOR of everything between '$' and '*' against the two hex digits after '*'.
bool checksumOk(const char* s) {
  if (s[0] != '$') return false;
  byte sum = 0;
  const char* p = s + 1;
  while (*p && *p != '*') sum ^= (byte)*p++;
  if (*p != '*' || hexValue(p[1]) < 0 || hexValue(p[2]) < 0) return false;
  return sum == hexValue(p[1]) * 16 + hexValue(p[2]);
}

// Field n (0: the talker and type) of a comma-separated sentence, copied into out.
void field(const char* s, int n, char* out, int size) {
  while (n > 0 && *s) if (*s++ == ',') --n;
  int i = 0;
  while (*s && *s != ',' && *s != '*' && i < size - 1) out[i++] = *s++;
  out[i] = 0;
}

// "ddmm.mmmmm" (degrees digits: 2 for latitude, 3 for longitude) to millionths of a degree, rounded.
long millionths(const char* text, int degreeDigits) {
  long degrees = 0, minutes = 0;  // minutes in hundred-thousandths
  int i = 0;
  for (; i < degreeDigits && text[i]; ++i) degrees = degrees * 10 + (text[i] - '0');
  for (; text[i] && text[i] != '.'; ++i) minutes = minutes * 10 + (text[i] - '0');
  int decimals = 0;
  if (text[i] == '.')
    for (++i; text[i] && decimals < 5; ++i, ++decimals) minutes = minutes * 10 + (text[i] - '0');
  for (; decimals < 5; ++decimals) minutes *= 10;
  return degrees * 1000000L + (minutes * 10 + 30) / 60;
}

void printDegrees(long e6) {
  if (e6 < 0) {
    Serial.print('-');
    e6 = -e6;
  }
  Serial.print(e6 / 1000000L);
  Serial.print('.');
  char digits[7];
  long frac = e6 % 1000000L;
  for (int i = 5; i >= 0; --i, frac /= 10) digits[i] = '0' + frac % 10;
  digits[6] = 0;
  Serial.print(digits);
}

void takeGga(const char* s) {
  char f[16];
  field(s, 6, f, sizeof f);
  if (f[0] == 0 || f[0] == '0') {
    Serial.println(F("no fix"));
    return;
  }
  char lat[16], ns[2], lon[16], ew[2], sats[4], alt[10];
  field(s, 2, lat, sizeof lat);
  field(s, 3, ns, sizeof ns);
  field(s, 4, lon, sizeof lon);
  field(s, 5, ew, sizeof ew);
  field(s, 7, sats, sizeof sats);
  field(s, 9, alt, sizeof alt);
  long latE6 = millionths(lat, 2), lonE6 = millionths(lon, 3);
  if (ns[0] == 'S') latE6 = -latE6;
  if (ew[0] == 'W') lonE6 = -lonE6;
  Serial.print(F("fix "));
  printDegrees(latE6);
  Serial.print(' ');
  printDegrees(lonE6);
  Serial.print(F(" sats "));
  Serial.print(atoi(sats));
  Serial.print(F(" alt "));
  Serial.println(alt);
}

void setup() {
  Serial.begin(115200);
  Serial1.begin(BAUD);
  Serial.println(F("gps: listening on Serial1"));
}

void loop() {
  while (Serial1.available()) {
    const char c = Serial1.read();
    if (c == '$') length = 0;
    if (c == '\r' || c == '\n') {
      if (length == 0) continue;
      sentence[length] = 0;
      length = 0;
      if (!checksumOk(sentence)) {
        ++bad;
        continue;
      }
      ++good;
      if (strncmp(sentence, "$GPGGA,", 7) == 0) takeGga(sentence);
      continue;
    }
    if (length < (int)sizeof sentence - 1) sentence[length++] = c;
  }
}
