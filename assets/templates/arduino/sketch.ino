// @NAME@: an Arduino sketch on SEAR's default Arduino robot (the bundled rover: an Arduino Mega 2560,
// a Motor Shield R3 for the two wheels, an HC-SR04 looking ahead). It drives forwards and turns
// a quarter turn on the spot whenever the sonar sees something closer than STOP_CM, printing each
// reading.
// `sear run .` builds it against SEAR's Arduino layer and runs it; the same sketch builds for the
// board in the Arduino IDE (docs/arduino.md in SEAR says what the layer models).

// Motor Shield R3: channel A drives the left wheel, channel B the right one.
const uint8_t LEFT_PWM = 3;
const uint8_t LEFT_DIR = 12;
const uint8_t LEFT_BRAKE = 9;
const uint8_t RIGHT_PWM = 11;
const uint8_t RIGHT_DIR = 13;
const uint8_t RIGHT_BRAKE = 8;
// The HC-SR04: its echo on pin 2 (interrupt 0), should you want attachInterrupt() instead.
const uint8_t TRIG = 24;
const uint8_t ECHO = 2;

const int SPEED = 150;     // of 255: about 0.4 m/s on the rover
const long STOP_CM = 40;   // turn when anything is closer than this
const int TURN_MS = 430;   // a quarter turn on the spot at SPEED; tune it on your floor

void motor(uint8_t pwm, uint8_t dir, uint8_t brake, int speed) {
  digitalWrite(brake, LOW);
  digitalWrite(dir, speed >= 0 ? HIGH : LOW);
  analogWrite(pwm, abs(speed));
}

void drive(int left, int right) {
  motor(LEFT_PWM, LEFT_DIR, LEFT_BRAKE, left);
  motor(RIGHT_PWM, RIGHT_DIR, RIGHT_BRAKE, right);
}

// Centimetres to the nearest echo, or -1 when none came back within 30 ms (beyond ~5 m).
long distance_cm() {
  digitalWrite(TRIG, HIGH);
  delayMicroseconds(10);
  digitalWrite(TRIG, LOW);
  const unsigned long us = pulseIn(ECHO, HIGH, 30000UL);
  return us ? (long)(us / 58) : -1;
}

void setup() {
  Serial.begin(115200);
  pinMode(TRIG, OUTPUT);
  pinMode(ECHO, INPUT);
  pinMode(LEFT_DIR, OUTPUT);
  pinMode(LEFT_BRAKE, OUTPUT);
  pinMode(RIGHT_DIR, OUTPUT);
  pinMode(RIGHT_BRAKE, OUTPUT);
  Serial.println(F("@NAME@ ready"));
}

void loop() {
  const long cm = distance_cm();
  Serial.print(F("distance "));
  Serial.print(cm);
  Serial.println(F(" cm"));
  if (cm >= 0 && cm < STOP_CM) {
    drive(SPEED, -SPEED);
    delay(TURN_MS);
  }
  drive(SPEED, SPEED);
  delay(60);  // the HC-SR04 wants 60 ms between pings
}
