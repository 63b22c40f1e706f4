/* Proves that the sanitizer build really catches errors here: run as "asan" it overflows a
 * heap buffer, as "leak" it leaks a block, as "ubsan" it overflows a signed integer; ctest
 * expects each sanitizer's report in the output. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv) {
  volatile int big = 2147483647;
  char *p;
  int r;
  if (argc < 2) return 2;
  if (strcmp(argv[1], "asan") == 0) {
    p = (char *)malloc(8);
    memset(p, 0, 9); /* one byte too many */
    r = p[3];
    free(p);
    return r;
  }
  if (strcmp(argv[1], "leak") == 0) {
    p = (char *)malloc(64);
    p[0] = 1;
    p = NULL; /* the only pointer is gone */
    return 0;
  }
  printf("%d\n", big + argc); /* signed overflow */
  return 0;
}
