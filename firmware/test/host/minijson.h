/* A small JSON reader for the test vectors (tests only). */
#ifndef MINIJSON_H
#define MINIJSON_H
#include <stddef.h>

typedef enum { J_NULL, J_BOOL, J_NUM, J_STR, J_ARR, J_OBJ } jtype_t;

typedef struct jnode {
    jtype_t type;
    double num;           /* J_NUM, J_BOOL (0/1) */
    char *str;            /* J_STR */
    char *key;            /* member name inside an object */
    struct jnode *child;  /* first element / member */
    struct jnode *next;   /* next sibling */
} jnode_t;

jnode_t *json_load(const char *path);            /* NULL on error (message on stderr) */
jnode_t *json_get(const jnode_t *obj, const char *key);
long json_int(const jnode_t *obj, const char *key, long dflt);
const char *json_str(const jnode_t *obj, const char *key);
/* hex string -> bytes; returns the byte count or -1 */
int hex_decode(const char *hex, unsigned char *out, int cap);
#endif
