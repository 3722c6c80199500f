#include "minijson.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *p;
/* loaded documents stay reachable from here until exit (the tests never free them) */
static void *keep[16];
static int nkeep;

static jnode_t *node(jtype_t t)
{
    jnode_t *n = calloc(1, sizeof *n);
    if (!n) {
        perror("calloc");
        exit(2);
    }
    n->type = t;
    return n;
}

static void ws(void)
{
    while (*p && isspace((unsigned char)*p))
        p++;
}

static jnode_t *value(void);

static char *string(void)
{
    /* *p == '"'; escapes other than \" \\ \/ \n \t are kept verbatim (not needed by the vectors) */
    p++;
    size_t cap = 64, n = 0;
    char *s = malloc(cap);
    while (*p && *p != '"') {
        char c = *p++;
        if (c == '\\' && *p) {
            c = *p++;
            if (c == 'n')
                c = '\n';
            else if (c == 't')
                c = '\t';
        }
        if (n + 2 > cap)
            s = realloc(s, cap *= 2);
        s[n++] = c;
    }
    if (*p == '"')
        p++;
    s[n] = 0;
    return s;
}

static jnode_t *value(void)
{
    ws();
    jnode_t *n;
    if (*p == '{' || *p == '[') {
        char close = *p == '{' ? '}' : ']';
        n = node(*p == '{' ? J_OBJ : J_ARR);
        p++;
        jnode_t **tail = &n->child;
        for (;;) {
            ws();
            if (*p == close) {
                p++;
                break;
            }
            char *key = NULL;
            if (n->type == J_OBJ) {
                if (*p != '"')
                    return NULL;
                key = string();
                ws();
                if (*p++ != ':')
                    return NULL;
            }
            jnode_t *v = value();
            if (!v)
                return NULL;
            v->key = key;
            *tail = v;
            tail = &v->next;
            ws();
            if (*p == ',')
                p++;
        }
        return n;
    }
    if (*p == '"') {
        n = node(J_STR);
        n->str = string();
        return n;
    }
    if (!strncmp(p, "true", 4) || !strncmp(p, "false", 5)) {
        n = node(J_BOOL);
        n->num = *p == 't';
        p += *p == 't' ? 4 : 5;
        return n;
    }
    if (!strncmp(p, "null", 4)) {
        p += 4;
        return node(J_NULL);
    }
    char *end;
    double d = strtod(p, &end);
    if (end == p)
        return NULL;
    p = end;
    n = node(J_NUM);
    n->num = d;
    return n;
}

jnode_t *json_load(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        perror(path);
        return NULL;
    }
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)len + 1);
    if (fread(buf, 1, (size_t)len, f) != (size_t)len) {
        fclose(f);
        return NULL;
    }
    fclose(f);
    buf[len] = 0;
    p = buf;
    jnode_t *root = value();
    if (!root)
        fprintf(stderr, "%s: JSON syntax error near offset %ld\n", path, (long)(p - buf));
    if (nkeep < 15) {
        keep[nkeep++] = buf;
        keep[nkeep++] = root;
    }
    return root;
}

jnode_t *json_get(const jnode_t *obj, const char *key)
{
    if (!obj || obj->type != J_OBJ)
        return NULL;
    for (jnode_t *c = obj->child; c; c = c->next)
        if (c->key && !strcmp(c->key, key))
            return c;
    return NULL;
}

long json_int(const jnode_t *obj, const char *key, long dflt)
{
    jnode_t *n = json_get(obj, key);
    return n && (n->type == J_NUM || n->type == J_BOOL) ? (long)n->num : dflt;
}

const char *json_str(const jnode_t *obj, const char *key)
{
    jnode_t *n = json_get(obj, key);
    return n && n->type == J_STR ? n->str : NULL;
}

int hex_decode(const char *hex, unsigned char *out, int cap)
{
    int n = 0;
    while (hex[0] && hex[1]) {
        unsigned v;
        if (n >= cap || sscanf(hex, "%2x", &v) != 1)
            return -1;
        out[n++] = (unsigned char)v;
        hex += 2;
    }
    return hex[0] ? -1 : n;
}
