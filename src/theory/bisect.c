/* bisect: placeholder, being written (issue 5). */
typedef int gr_placeholder_bisect;
