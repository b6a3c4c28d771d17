// The first servo takes Timer5, as on a Mega: PWM on pin 45 afterwards is refused at run time.
#include <Servo.h>

Servo arm;

void setup() {
  Serial.begin(115200);
  arm.attach(30);
  Serial.println("attached");
  analogWrite(45, 100);
  Serial.println("not reached");
}

void loop() {}
