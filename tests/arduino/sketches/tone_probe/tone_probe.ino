// tone() and noTone() on Timer2, for sketch_run_test.cpp: a timed note, a note on a second pin
// while it plays (ignored: one tone at a time), PWM on pin 9 stopped by the tone, a note until
// noTone(), a frequency too low for Timer2's compare register, and PWM on pin 10 once it is free.
void setup() {
  Serial.begin(115200);
  analogWrite(9, 128);
  tone(8, 440, 100);
  tone(11, 2000);
  delay(200);
  tone(8, 1000);
  delay(20);
  noTone(8);
  delay(50);
  tone(8, 30, 100);
  delay(150);
  analogWrite(10, 64);
  Serial.println("done");
}

void loop() {}
