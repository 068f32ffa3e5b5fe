/* Contact parameters from a short "key=value key=value" list (the collision tests' cases). */
#ifndef GR_TEST_CONTACT_SETTINGS_H
#define GR_TEST_CONTACT_SETTINGS_H

#include <check.h>
#include <stdio.h>
#include <string.h>

#include "granule/model.h"

static inline void contact_settings(gr_contact_params *p, const char *settings)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s", settings);
    for (char *save = NULL, *tok = strtok_r(buf, " ", &save); tok;
         tok = strtok_r(NULL, " ", &save)) {
        char *eq = strchr(tok, '=');
        ck_assert(eq);
        *eq = '\0';
        gr_error err = {0};
        ck_assert_msg(gr_contact_set(p, tok, eq + 1, &err) == GR_OK, "%s", err.message);
    }
}

#endif
