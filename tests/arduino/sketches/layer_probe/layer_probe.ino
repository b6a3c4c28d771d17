// A clean-room sketch over the Arduino layer, for layer_test.cpp: each line it prints is one
// function's result against the rover's HC-SR04, MPU-6050 and HMC5883L. report() is used before
// it is defined, so the sketch builds only if the IDE's prototypes are generated.
#include <EEPROM.h>
#include <Servo.h>
#include <Wire.h>

#include "probe_config.h"

Servo pan;
volatile unsigned long edges = 0;

void onEcho() { edges++; }

void setup() {
  Serial.begin(115200);
  while (!Serial) {
  }
  report(F("start"), millis());

  // Print and String from Debian's core: numbers in bases, floats, concatenation.
  Serial.print(255, HEX);
  Serial.print(' ');
  Serial.print(255, BIN);
  Serial.print(' ');
  Serial.println(3.14159, 3);
  String s = String("pin ") + LED_BUILTIN + " A0 " + A0 + " int " + digitalPinToInterrupt(2) + digitalPinToInterrupt(3) +
             digitalPinToInterrupt(21) + digitalPinToInterrupt(18);
  s.replace("pin", "led");
  Serial.println(s);

  // Wire: write-then-read with a repeated start, to both chips; then a missing address.
  Wire.begin();
  Wire.setClock(400000);
  Wire.beginTransmission(IMU_ADDRESS);
  Wire.write(0x75); // WHO_AM_I
  const uint8_t sent = Wire.endTransmission(false);
  const uint8_t got = Wire.requestFrom(IMU_ADDRESS, 1);
  Serial.print(F("imu "));
  Serial.print(sent);
  Serial.print(' ');
  Serial.print(got);
  Serial.print(' ');
  Serial.println(Wire.read(), HEX);
  Wire.beginTransmission(COMPASS_ADDRESS);
  Wire.write(0x0A);
  Wire.endTransmission();
  Wire.requestFrom(COMPASS_ADDRESS, 3);
  Serial.print(F("compass "));
  while (Wire.available()) Serial.write(Wire.read());
  Serial.println();
  Wire.beginTransmission(0x50);
  Wire.write(0);
  report(F("absent"), Wire.endTransmission());

  // EEPROM through Debian's library, unchanged: erased cells, then a value put and got back.
  report(F("eeprom length"), EEPROM.length());
  report(F("eeprom erased"), EEPROM.read(17));
  float f = 2.5f;
  EEPROM.put(20, f);
  float g = 0;
  EEPROM.get(20, g);
  Serial.print(F("eeprom float "));
  Serial.println(g, 2);

  pan.attach(SERVO_PIN);
  pan.write(90);
  report(F("servo us"), pan.readMicroseconds());

  pinMode(TRIG_PIN, OUTPUT);
  pinMode(ECHO_PIN, INPUT);
  attachInterrupt(digitalPinToInterrupt(ECHO_PIN), onEcho, CHANGE);
}

void loop() {
  delay(70);
  digitalWrite(TRIG_PIN, HIGH);
  delayMicroseconds(10);
  digitalWrite(TRIG_PIN, LOW);
  const unsigned long width = pulseIn(ECHO_PIN, HIGH, 30000UL);
  report(F("echo us"), width);
  report(F("edges"), edges);
}

void report(const __FlashStringHelper *what, unsigned long value) {
  Serial.print(what);
  Serial.print(' ');
  Serial.println(value);
}
