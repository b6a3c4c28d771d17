// An HC-SR04 read the way the Arduino examples read a ping sensor: a 10 us pulse on TRIG, pulseIn on
// ECHO, and the time turned into centimetres at 29 us per centimetre each way. Prints one line per
// reading, every 100 ms (the module wants at least 60 ms between measurements).
const int TRIG = 24;
const int ECHO = 10;

long microsecondsToCentimeters(long microseconds) { return microseconds / 29 / 2; }

void setup() {
  Serial.begin(115200);
  pinMode(TRIG, OUTPUT);
  pinMode(ECHO, INPUT);
}

void loop() {
  digitalWrite(TRIG, LOW);
  delayMicroseconds(2);
  digitalWrite(TRIG, HIGH);
  delayMicroseconds(10);
  digitalWrite(TRIG, LOW);
  const long duration = pulseIn(ECHO, HIGH);
  Serial.print(duration);
  Serial.print(F(" us, "));
  Serial.print(microsecondsToCentimeters(duration));
  Serial.println(F(" cm"));
  delay(100);
}
