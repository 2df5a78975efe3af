// The isoimpact program; the tutorial-style main program is being written.
#include <iostream>

int
main()
{
  std::cout << "isoimpact" << std::endl;
  return 0;
}
