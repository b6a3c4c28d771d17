// A hobby servo swept from 0 to 180 degrees and back, a degree every 15 ms, as the Servo library's
// classic example does; the pulse width of each step is printed every 30 degrees.
#include <Servo.h>

const int SERVO_PIN = 5;  // any pin: Servo makes its pulses from a timer's interrupt
Servo sweeper;

void sweep(int from, int to) {
  const int step = from < to ? 1 : -1;
  for (int angle = from; angle != to + step; angle += step) {
    sweeper.write(angle);
    if (angle % 30 == 0) {
      Serial.print(angle);
      Serial.print(F(" deg: "));
      Serial.print(sweeper.readMicroseconds());
      Serial.println(F(" us"));
    }
    delay(15);
  }
}

void setup() {
  Serial.begin(115200);
  sweeper.attach(SERVO_PIN);
}

void loop() {
  sweep(0, 180);
  sweep(180, 0);
}
