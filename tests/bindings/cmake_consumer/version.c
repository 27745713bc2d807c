/* Prints the version through the C API (ppohdem::c). */
#include <stdio.h>
#include <string.h>

#include "ppohdem/ppohdem.h"

int main(void) {
  printf("ppohdem %s\n", ppohdem_version());
  return strcmp(ppohdem_version(), "") == 0;
}
