/* Synthetic pairs for the memory and speed checks of `contactmap pairs sort` and `pairs dedup`
 * (docs/performance.md): N pairs with a 4DN pairs header on standard output, fast enough for
 * 100 M pairs (a few hundred MB/s), seeded.
 *
 *   cc -O2 -o /tmp/pairs_synthetic scripts/pairs_synthetic.c
 *   /tmp/pairs_synthetic N random SEED   # uniform positions: the input of `pairs sort`
 *   /tmp/pairs_synthetic N sorted SEED   # pairtools' sort order, about 10% duplicates (exact or
 *                                        # shifted by 0-3 bp): the input of `pairs dedup`
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint64_t state;
static uint64_t next(void) { /* splitmix64 */
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static const char *names[4] = {"chr1", "chr2", "chr3", "chr4"};
static const uint64_t lengths[4] = {250000000, 240000000, 200000000, 190000000};

int main(int argc, char **argv) {
    if (argc != 4 || (strcmp(argv[2], "random") && strcmp(argv[2], "sorted"))) {
        fprintf(stderr, "usage: %s N random|sorted SEED\n", argv[0]);
        return 2;
    }
    uint64_t n = strtoull(argv[1], NULL, 10);
    state = strtoull(argv[3], NULL, 10);
    static char buffer[1 << 20];
    setvbuf(stdout, buffer, _IOFBF, sizeof buffer);
    printf("## pairs format v1.0.0\n#shape: upper triangle\n#genome_assembly: synthetic\n");
    for (int c = 0; c < 4; c++) printf("#chromsize: %s %llu\n", names[c], (unsigned long long)lengths[c]);
    printf("#columns: readID chrom1 pos1 chrom2 pos2 strand1 strand2 pair_type\n");
    if (!strcmp(argv[2], "random")) {
        for (uint64_t i = 0; i < n; i++) {
            uint64_t r = next(), c1 = r & 3, c2 = (r >> 2) & 3;
            printf("r%llu\t%s\t%llu\t%s\t%llu\t%c\t%c\tUU\n", (unsigned long long)i, names[c1],
                   (unsigned long long)(1 + next() % lengths[c1]), names[c2],
                   (unsigned long long)(1 + next() % lengths[c2]), (r >> 4) & 1 ? '+' : '-',
                   (r >> 5) & 1 ? '+' : '-');
        }
        return 0;
    }
    /* Sorted: cis pairs of each chromosome with pos1 rising; a pair is followed by a duplicate
     * (same or shifted by up to 3 bp, never before it) with probability 1/10. */
    uint64_t i = 0;
    for (int c = 0; c < 4; c++) {
        uint64_t count = c < 3 ? n / 4 : n - 3 * (n / 4);
        uint64_t step = lengths[c] / (count + 1), pos1 = 1, last2 = 0, last1 = 0;
        char strand1 = '+', strand2 = '+';
        for (uint64_t k = 0; k < count; k++, i++) {
            uint64_t r = next(), pos2;
            if (k > 0 && r % 10 == 0) { /* a duplicate of the pair above */
                pos1 = last1 + ((r >> 8) & 3);
                pos2 = last2 + ((r >> 10) & 3);
            } else {
                pos1 = last1 + 1 + next() % (2 * step);
                pos2 = pos1 + (next() % 1000000);
                strand1 = (r >> 4) & 1 ? '+' : '-';
                strand2 = (r >> 5) & 1 ? '+' : '-';
            }
            if (pos1 == last1 && pos2 < last2) pos2 = last2;
            printf("s%llu\t%s\t%llu\t%s\t%llu\t%c\t%c\tUU\n", (unsigned long long)i, names[c],
                   (unsigned long long)pos1, names[c], (unsigned long long)pos2, strand1, strand2);
            last1 = pos1;
            last2 = pos2;
        }
    }
    return 0;
}
