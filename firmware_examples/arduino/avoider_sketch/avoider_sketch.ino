// The obstacle avoider of firmware_examples/avoider as an Arduino sketch: the same rover, sensors,
// motors and decisions, written against the Arduino API instead of SEAR's C HAL. Two Sharp GP2D12
// rangers ahead-left and ahead-right on A0 and A1, a GP2D15 straight ahead on pin 22, a bump switch
// on pin 2 (interrupt 0), two DC motors on an Arduino Motor Shield R3.

const int IR_LEFT = A0;
const int IR_RIGHT = A1;
const int IR_FRONT = 22;  // GP2D15: HIGH while something is within about 24 cm
const int BUMP = 2;       // switch to ground, closes on contact

// Motor Shield R3: channel A drives the left motor, channel B the right one.
const int LEFT_PWM = 3, LEFT_DIR = 12, LEFT_BRAKE = 9;
const int RIGHT_PWM = 11, RIGHT_DIR = 13, RIGHT_BRAKE = 8;

const int CRUISE = 150;  // PWM duty of 255
const int TURN = 130;
const int NEAR_CM = 30;          // turn away below this
const int VEER_CM = 55;          // steer away below this
const int CLEAR_MARGIN_CM = 10;  // stop veering only this far beyond VEER_CM, or it would dither
const int FAR_CM = 80;           // the GP2D12's range ends here

enum State { CRUISING, VEERING_LEFT, VEERING_RIGHT, TURNING_LEFT, TURNING_RIGHT };
const char *const stateNames[] = {"cruising", "veering left", "veering right", "turning left", "turning right"};

volatile bool bumped = false;
State state = CRUISING;
unsigned long nextReport = 0;

void onBump() { bumped = true; }

// One motor: speed -255..255, negative backwards.
void motor(int pwmPin, int dirPin, int brakePin, int speed) {
  digitalWrite(brakePin, LOW);
  digitalWrite(dirPin, speed >= 0 ? HIGH : LOW);
  analogWrite(pwmPin, abs(speed));
}

void drive(int left, int right) {
  motor(LEFT_PWM, LEFT_DIR, LEFT_BRAKE, left);
  motor(RIGHT_PWM, RIGHT_DIR, RIGHT_BRAKE, right);
}

// Distance from a GP2D12 reading (10-bit, 5 V reference), the usual fit to the datasheet's curve:
// cm = 6787 / (code - 3) - 4, good over 10..80 cm.
int irCm(int pin) {
  const unsigned int code = analogRead(pin);
  if (code < 84) return FAR_CM;
  const unsigned int cm = 6787u / (code - 3u) - 4u;
  return cm > (unsigned)FAR_CM ? FAR_CM : (int)cm;
}

void report(const char *what, int left, int right, bool front) {
  Serial.print(what);
  Serial.print(F(" (L "));
  Serial.print(left);
  Serial.print(F(" cm, R "));
  Serial.print(right);
  Serial.print(F(" cm, front "));
  Serial.print(front ? F("near") : F("clear"));
  Serial.print(F(")\r\n"));
}

void setup() {
  Serial.begin(115200);
  pinMode(LEFT_DIR, OUTPUT);
  pinMode(LEFT_BRAKE, OUTPUT);
  pinMode(RIGHT_DIR, OUTPUT);
  pinMode(RIGHT_BRAKE, OUTPUT);
  pinMode(IR_FRONT, INPUT);
  pinMode(BUMP, INPUT_PULLUP);
  attachInterrupt(digitalPinToInterrupt(BUMP), onBump, FALLING);
  Serial.print(F("avoider: ready\r\n"));
  delay(100);  // the rangers' first measurement is ready after one 38 ms cycle
}

void loop() {
  const int left = irCm(IR_LEFT);
  const int right = irCm(IR_RIGHT);
  const bool front = digitalRead(IR_FRONT) == HIGH;

  State next;
  if (bumped) {
    Serial.print(F("bump: backing off\r\n"));
    drive(-TURN, -TURN);
    delay(400);
    drive(-TURN, TURN);
    delay(350);
    bumped = false;
    next = CRUISING;
  } else if (front || left < NEAR_CM || right < NEAR_CM) {
    // Turn on the spot away from the nearer side, and keep turning the same way until clear.
    if (state == TURNING_LEFT || state == TURNING_RIGHT) next = state;
    else next = left < right ? TURNING_RIGHT : TURNING_LEFT;
  } else if (left < VEER_CM || (state == VEERING_RIGHT && left < VEER_CM + CLEAR_MARGIN_CM)) {
    next = VEERING_RIGHT;
  } else if (right < VEER_CM || (state == VEERING_LEFT && right < VEER_CM + CLEAR_MARGIN_CM)) {
    next = VEERING_LEFT;
  } else {
    next = CRUISING;
  }
  switch (next) {
    case TURNING_LEFT: drive(-TURN, TURN); break;
    case TURNING_RIGHT: drive(TURN, -TURN); break;
    case VEERING_LEFT: drive(CRUISE / 3, CRUISE); break;
    case VEERING_RIGHT: drive(CRUISE, CRUISE / 3); break;
    default: drive(CRUISE, CRUISE); break;
  }
  if (next != state) {
    report(stateNames[next], left, right, front);
    state = next;
  }
  if (millis() >= nextReport) {
    nextReport += 10000;
    report("still going", left, right, front);
  }
  delay(20);
}
