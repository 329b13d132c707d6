// evsim: command-line runner on the core library.
#include <iostream>

int main() {
  std::cout << "evsim\n";
  return 0;
}
