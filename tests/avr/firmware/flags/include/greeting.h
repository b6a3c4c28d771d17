/* Found only through the include folder the test project names (<firmware includes>). */
#ifndef GREETING_H
#define GREETING_H
#define GREETING "flags: hello"
int twice(int x); /* in twice.cpp, compiled as C++ */
#endif
