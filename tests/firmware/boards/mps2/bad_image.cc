// A deliberately bad "image": heap, double arithmetic and exception support. The symbol check must
// reject it.
#include <new>

extern "C" void _start() {}

double Scale(double v) { return v * 1.5 + 0.25; }

int* Leak() { return new int(3); }

int main() { return static_cast<int>(Scale(2.0)) + *Leak(); }
