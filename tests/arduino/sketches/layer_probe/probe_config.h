// The rover's wiring for layer_probe.ino (layer_test.cpp writes the same into its project).
#pragma once

#define TRIG_PIN 24
#define ECHO_PIN 2 // INT4: pulseIn and an interrupt on the same pin
#define SERVO_PIN 30
#define IMU_ADDRESS 0x68
#define COMPASS_ADDRESS 0x1E
